"""A damaged bag: never read as if it were whole; what is intact is read only when allowed, and recovered.

The reference bag is cut at every 1 % of its size and has single bytes flipped at seeded
offsets. Whatever the damage, ``read_bag`` refuses it in one line naming the damage, and
with damage allowed either refuses in one line or returns messages that are all in the
original, names the damage unless nothing read differs from the original, and
``recover_bag`` then writes a finalized bag that the indexed MCAP reader and rosbags open
with exactly those messages. Every command that reads bags, run on copies of the smallest
reference bag (rewritten by the recorder's writer, as runs write bags now) with a byte
flipped at seeded offsets, refuses naming the damage or, given ``--allow-damaged``, says
what it skipped: none exits 0 silently, none prints a traceback, none hangs.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader

from tether_bringup.bag_info import bag_summary_lines
from tether_bringup.bag_reader import damaged_bags_allowed
from tether_bringup.bag_reader import read_bag
from tether_bringup.bag_writer import BagWriter
from tether_bringup.bag_recover import recover_bag
from tether_bringup.errors import BagError

from tethersim_testing import tethersim

REFERENCE = Path(__file__).resolve().parent.parent / 'bags' / 'platform-hpr3-10s'
ORIGINAL = read_bag(REFERENCE)
ORIGINAL_SET = {(m.topic, m.log_time, m.data) for m in ORIGINAL.messages}
DATA = ORIGINAL.path.read_bytes()


def _bag_dir(tmp_path: Path, content: bytes, name: str) -> Path:
    directory = tmp_path / name
    directory.mkdir()
    (directory / f'{name}_0.mcap').write_bytes(content)
    return directory


def _check_damaged_copy(directory: Path) -> None:
    """Read a damaged copy; if anything is recoverable, recover it and check the finalized bag."""
    try:
        bag = read_bag(directory, allow_damaged=True)
    except BagError as error:
        assert '\n' not in str(error) and str(error).strip()
        return
    read = [(m.topic, m.log_time, m.data) for m in bag.messages]
    assert set(read) <= ORIGINAL_SET
    for topic in bag.topics.values():
        assert (topic.type_name, topic.definition, topic.type_hash) == (
            ORIGINAL.topics[topic.name].type_name, ORIGINAL.topics[topic.name].definition,
            ORIGINAL.topics[topic.name].type_hash)
    if bag.complete:
        assert read == [(m.topic, m.log_time, m.data) for m in ORIGINAL.messages]
        assert {t.name: t.definition for t in bag.topics.values()} == \
            {t.name: t.definition for t in ORIGINAL.topics.values()}
        return
    with pytest.raises(BagError, match=' is damaged at byte ') as refused:
        read_bag(directory)
    assert '\n' not in str(refused.value) and '--allow-damaged' in str(refused.value)
    lines = bag_summary_lines(directory)
    assert lines[-1].startswith('damaged at byte ')
    recovery = recover_bag(directory)
    assert recovery is not None and recovery.damaged_copy.exists()
    finalized = read_bag(directory)
    assert finalized.complete
    assert [(m.topic, m.log_time, m.data) for m in finalized.messages] == read
    with open(finalized.path, 'rb') as stream:
        indexed = make_reader(stream)
        assert indexed.get_summary().statistics.message_count == len(read)
        assert sum(1 for _ in indexed.iter_messages()) == len(read)
    with AnyReader([directory]) as reader:
        assert reader.message_count == len(read)


@pytest.mark.parametrize('percent', range(0, 100))
def test_bag_cut_at_every_percent(tmp_path, percent):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * percent // 100], 'cut')
    _check_damaged_copy(directory)
    if percent >= 60:
        assert len(read_bag(directory, allow_damaged=True).messages) > 0.5 * len(ORIGINAL.messages)


@pytest.mark.parametrize('seed', range(40))
def test_bag_with_flipped_bytes(tmp_path, seed):
    rng = np.random.default_rng(seed)
    content = bytearray(DATA)
    for offset in rng.integers(0, len(DATA), size=5):
        content[offset] ^= int(rng.integers(1, 256))
    _check_damaged_copy(_bag_dir(tmp_path, bytes(content), 'flipped'))


def test_a_flipped_byte_inside_a_chunk_skips_that_chunk_only(tmp_path):
    content = bytearray(DATA)
    content[len(DATA) // 2] ^= 0xFF  # inside the compressed data of the middle chunk
    bag = read_bag(_bag_dir(tmp_path, bytes(content), 'flipped'), allow_damaged=True)
    assert len(bag.damage) == 1
    assert bag.damage[0].reason.startswith('Chunk (sim time ')
    assert 'is corrupt' in bag.damage[0].reason
    lost = {topic: count - bag.topics[topic].count for topic, count in
            ((name, topic.count) for name, topic in ORIGINAL.topics.items())}
    assert bag.damage[0].lost_topics == {topic: count for topic, count in lost.items() if count}
    assert bag.lost_count == len(ORIGINAL.messages) - len(bag.messages)
    assert f'({bag.lost_count} messages lost: ' in str(bag.damage[0])
    kept = {m.log_time for m in bag.messages}
    assert min(kept) == ORIGINAL.messages[0].log_time and max(kept) == ORIGINAL.messages[-1].log_time
    assert 0.3 < len(bag.messages) / len(ORIGINAL.messages) < 0.9


def test_a_stub_says_what_is_wrong_in_one_line(tmp_path):
    stub = tmp_path / 'stub.mcap'
    stub.write_bytes(DATA[:100])
    result = tethersim('bag', 'info', str(stub), timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip() == (
        f'tethersim: error: {stub}: 100 bytes, damaged before any topic was recorded: byte 38: the Chunk record '
        f'begun here needs {int.from_bytes(DATA[39:47], "little")} bytes but the file ends 53 bytes later '
        '(cut short, or its length field is damaged) (messages lost: unknown, the file is not readable after this '
        'byte)')


def test_bag_info_of_a_cut_bag_lists_what_is_intact_and_where_it_is_cut(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 60 // 100], 'cut')
    result = tethersim('bag', 'info', str(directory), timeout=60)
    assert result.returncode == 0, result.stderr
    assert 'Traceback' not in result.stderr
    lines = result.stdout.strip().splitlines()
    assert 'DAMAGED' in lines[0]
    bag = read_bag(directory, allow_damaged=True)
    for name, topic in bag.topics.items():
        assert any(line.split()[:1] == [name] and line.split()[2] == str(topic.count) for line in lines)
    assert lines[-1] == f'damaged at {bag.damage_line()}'
    assert str(len(DATA) * 60 // 100) not in lines[-1] or 'ends' in lines[-1]


def test_bag_recover_command_finalizes_in_place_and_keeps_the_damaged_file(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 80 // 100], 'cut')
    before = read_bag(directory, allow_damaged=True)
    result = tethersim('bag', 'recover', str(directory), timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f'recovered {before.path}: {len(before.messages)} messages')
    assert 'an unknown number of messages dropped from 1 damaged place(s), the first at byte ' in result.stdout
    assert (directory / 'cut_0.mcap.damaged').read_bytes() == DATA[:len(DATA) * 80 // 100]
    assert (directory / 'metadata.yaml').exists()
    again = tethersim('bag', 'recover', str(directory), timeout=60)
    assert again.returncode == 0
    assert 'nothing to recover' in again.stdout


def test_replay_of_a_bag_with_nothing_intact_refuses_in_one_line(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 10 // 100], 'cut')
    result = tethersim('replay', str(directory), '--out', str(tmp_path / 'out'), timeout=60)
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1
    assert 'damaged before any topic was recorded' in result.stderr
    assert not (tmp_path / 'out').exists()


def test_replay_of_a_cut_bag_replays_exactly_its_intact_messages(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 60 // 100], 'cut')
    intact = read_bag(directory, allow_damaged=True)
    refused = tethersim('replay', str(directory), '--out', str(tmp_path / 'out'), '--rate', 'max', timeout=120)
    assert refused.returncode == 2
    assert refused.stderr.strip().splitlines() == [
        f'tethersim: error: {intact.path} is damaged at {intact.damage_line()}; refused: --allow-damaged reads '
        'what is intact, `tethersim bag recover` rewrites it']
    assert not (tmp_path / 'out').exists()
    result = tethersim('replay', str(directory), '--out', str(tmp_path / 'out'), '--rate', 'max', '--allow-damaged',
                       timeout=120)
    assert result.returncode == 0, result.stderr
    assert 'Traceback' not in result.stderr
    warning = [line for line in result.stderr.splitlines() if 'warning' in line]
    assert len(warning) == 1 and f'damaged at {intact.damage_line()}' in warning[0]
    replayed = read_bag(tmp_path / 'out' / 'bag')
    assert replayed.complete

    def payloads(bag):
        return sorted((m.topic, m.data) for m in bag.messages if m.topic != '/clock')

    assert payloads(replayed) == payloads(intact)


def test_report_reads_a_cut_bag_only_when_allowed(tmp_path):
    from psr_platform_sim.report import tracking_report
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 70 // 100], 'cut')
    with pytest.raises(BagError, match=' is damaged at byte '):
        tracking_report(str(directory), str(tmp_path / 'out'))
    with damaged_bags_allowed() as damaged:
        lines = tracking_report(str(directory), str(tmp_path / 'out'))
    assert [bag.path for bag in damaged] == [read_bag(directory, allow_damaged=True).path]
    count = read_bag(directory, allow_damaged=True).topics['/platform/state'].count
    assert lines[0].startswith(f'platform: {count} states')
    assert 0 < count < ORIGINAL.topics['/platform/state'].count


def test_copy_of_reference_bag_is_complete(tmp_path):
    shutil.copytree(REFERENCE, tmp_path / 'copy')
    assert read_bag(tmp_path / 'copy').complete
    assert recover_bag(tmp_path / 'copy') is None


def _as_recorded_now(bag, directory: Path) -> Path:
    """Write ``bag``'s messages with the recorder's writer (1 s chunks, every CRC) into ``directory``; its file."""
    writer = BagWriter(directory)
    for topic in bag.topics.values():
        writer.add_topic(topic.name, topic.type_name, topic.qos, topic.type_hash, definition=topic.definition)
    for message in bag.messages:
        writer.write(message.topic, message.data, message.log_time, message.publish_time)
    writer.close()
    return writer.path


def _flipped(tmp_path: Path, source: Path, offset: int, name: str) -> Path:
    """A bag directory holding ``source`` with the byte at ``offset`` inverted."""
    content = bytearray(source.read_bytes())
    content[offset] ^= 0xFF
    return _bag_dir(tmp_path, bytes(content), name)


def _names_the_damage(line: str) -> bool:
    return (' is damaged at byte ' in line or 'damaged before any topic was recorded: byte ' in line
            or 'not an MCAP file' in line)


def test_any_flipped_byte_of_a_bag_written_now_is_refused(tmp_path):
    """With every CRC MCAP has (chunks, data section, summary), no single flipped byte goes unnoticed."""
    recorded = _as_recorded_now(ORIGINAL, tmp_path / 'recorded')
    content = recorded.read_bytes()
    summary_start = int.from_bytes(content[-28:-20], 'little')  # the Footer's first field; its magic follows it
    data_end = summary_start - 13  # the DataEnd record: opcode, length, data-section CRC
    rng = np.random.default_rng(0)
    offsets = [*rng.integers(0, len(content), size=40), *rng.integers(data_end, len(content), size=20)]
    for offset in offsets:
        directory = _flipped(tmp_path, recorded, int(offset), f'flipped-{offset}')
        with pytest.raises(BagError) as refused:
            read_bag(directory)
        assert _names_the_damage(str(refused.value)), (offset, str(refused.value))
        shutil.rmtree(directory)


FLIP_SEEDS = range(3)
"""A handful of seeded offsets, each anywhere in the file: chunk data, chunk headers, indexes, summary."""


@pytest.mark.parametrize('seed', FLIP_SEEDS)
def test_every_command_refuses_a_flipped_bag_or_says_what_it_skipped(tmp_path, seed):
    recorded = _as_recorded_now(ORIGINAL, tmp_path / 'recorded')
    offset = int(np.random.default_rng(seed).integers(0, recorded.stat().st_size))
    bag = str(_flipped(tmp_path, recorded, offset, 'flipped'))
    refusing = {
        'bag info --check': ('bag', 'info', '--check', bag),
        'bag export': ('bag', 'export', bag, '--topic', '/platform/state', '--csv', str(tmp_path / 'state.csv')),
        'replay': ('replay', bag, '--out', str(tmp_path / 'replay'), '--rate', 'max'),
        'report surrogate': ('report', 'surrogate', bag, '--out', str(tmp_path / 'surrogate')),
        'report mission': ('report', 'mission', bag, '--out', str(tmp_path / 'mission')),
        'estimator evaluate': ('estimator', 'evaluate', bag, '--no-shift', '--out', str(tmp_path / 'evaluate')),
        'estimator tune': ('estimator', 'tune', bag, '--out', str(tmp_path / 'tune')),
    }
    for label, arguments in refusing.items():
        result = tethersim(*arguments, timeout=120)
        assert 'Traceback' not in result.stderr, (label, offset, result.stderr)
        assert result.returncode == 2, (label, offset, result.stdout, result.stderr)
        assert _names_the_damage(result.stderr.strip().splitlines()[-1]), (label, offset, result.stderr)
    assert not (tmp_path / 'replay').exists() and not (tmp_path / 'state.csv').exists()
    info = tethersim('bag', 'info', bag, timeout=120)
    export = tethersim('bag', 'export', bag, '--topic', '/platform/state', '--csv', str(tmp_path / 'state.csv'),
                       '--allow-damaged', timeout=120)
    recover = tethersim('bag', 'recover', bag, timeout=120)
    for label, result, said in (('bag info', info, 'damaged at byte '), ('bag export --allow-damaged', export,
                                'skipped at byte '), ('bag recover', recover, ' dropped from ')):
        assert 'Traceback' not in result.stderr, (label, offset, result.stderr)
        if result.returncode == 0:
            assert said in result.stdout, (label, offset, result.stdout)
        else:
            assert result.returncode == 2 and _names_the_damage(result.stderr), (label, offset, result.stderr)


def test_estimator_evaluate_with_allow_damaged_says_what_it_skipped(tmp_path):
    source = read_bag(REFERENCE.parent / 'estimator-still-40s')
    recorded = _as_recorded_now(source, tmp_path / 'recorded')
    bag = _flipped(tmp_path, recorded, recorded.stat().st_size // 2, 'flipped')
    damaged = read_bag(bag, allow_damaged=True)
    assert len(damaged.damage) == 1 and damaged.damage[0].reason.startswith('Chunk (sim time ')
    chunk = damaged.damage[0]
    first, last = (float(t) for t in chunk.reason.split('sim time ')[1].split(' s)')[0].split('-'))
    assert 0 < last - first <= 1.0
    assert chunk.lost_count == len(source.messages) - len(damaged.messages) > 0
    result = tethersim('estimator', 'evaluate', str(bag), '--no-shift', '--allow-damaged',
                       '--out', str(tmp_path / 'evaluate'), timeout=120)
    assert result.returncode == 0, result.stderr
    from relpos_estimator.recorded import TOPICS
    expected = read_bag(bag, list(TOPICS), allow_damaged=True).skipped_lines()
    assert expected[1] == f'  skipped at {chunk}'
    assert result.stdout.strip().splitlines()[-len(expected):] == expected
    assert (tmp_path / 'evaluate' / 'summary.txt').read_text().strip().splitlines()[-len(expected):] == expected
