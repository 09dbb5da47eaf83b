"""A damaged bag: every tool reads what is intact, names the damage, and recovery finalizes it.

The reference bag is cut at every 1 % of its size and has single bytes flipped at seeded
offsets. Whatever the damage, ``read_bag`` either refuses in one line or returns messages
that are all in the original, names the damage unless nothing read differs from the
original, and ``recover_bag`` then writes a finalized bag that the indexed MCAP reader and
rosbags open with exactly those messages.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader

from tether_bringup.bag_info import bag_summary_lines
from tether_bringup.bag_reader import read_bag
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
        bag = read_bag(directory)
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
        assert len(read_bag(directory).messages) > 0.5 * len(ORIGINAL.messages)


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
    bag = read_bag(_bag_dir(tmp_path, bytes(content), 'flipped'))
    assert len(bag.damage) == 1
    assert bag.damage[0].reason.startswith('Chunk (log time ')
    assert 'is corrupt' in bag.damage[0].reason
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
        '(cut short, or its length field is damaged)')


def test_bag_info_of_a_cut_bag_lists_what_is_intact_and_where_it_is_cut(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 60 // 100], 'cut')
    result = tethersim('bag', 'info', str(directory), timeout=60)
    assert result.returncode == 0, result.stderr
    assert 'Traceback' not in result.stderr
    lines = result.stdout.strip().splitlines()
    assert 'DAMAGED' in lines[0]
    bag = read_bag(directory)
    for name, topic in bag.topics.items():
        assert any(line.split()[:1] == [name] and line.split()[2] == str(topic.count) for line in lines)
    assert lines[-1] == f'damaged at {bag.damage_line()}'
    assert str(len(DATA) * 60 // 100) not in lines[-1] or 'ends' in lines[-1]


def test_bag_recover_command_finalizes_in_place_and_keeps_the_damaged_file(tmp_path):
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 80 // 100], 'cut')
    before = read_bag(directory)
    result = tethersim('bag', 'recover', str(directory), timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f'recovered {before.path}: {len(before.messages)} messages')
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
    intact = read_bag(directory)
    result = tethersim('replay', str(directory), '--out', str(tmp_path / 'out'), '--rate', 'max', timeout=120)
    assert result.returncode == 0, result.stderr
    assert 'Traceback' not in result.stderr
    warning = [line for line in result.stderr.splitlines() if 'warning' in line]
    assert len(warning) == 1 and f'damaged at {intact.damage_line()}' in warning[0]
    replayed = read_bag(tmp_path / 'out' / 'bag')
    assert replayed.complete

    def payloads(bag):
        return sorted((m.topic, m.data) for m in bag.messages if m.topic != '/clock')

    assert payloads(replayed) == payloads(intact)


def test_report_reads_a_cut_bag(tmp_path):
    from psr_platform_sim.report import tracking_report
    directory = _bag_dir(tmp_path, DATA[:len(DATA) * 70 // 100], 'cut')
    lines = tracking_report(str(directory), str(tmp_path / 'out'))
    count = read_bag(directory).topics['/platform/state'].count
    assert lines[0].startswith(f'platform: {count} states')
    assert 0 < count < ORIGINAL.topics['/platform/state'].count


def test_copy_of_reference_bag_is_complete(tmp_path):
    shutil.copytree(REFERENCE, tmp_path / 'copy')
    assert read_bag(tmp_path / 'copy').complete
    assert recover_bag(tmp_path / 'copy') is None
