"""Failure paths of the bringup: bad scenes, a crashing node, Ctrl-C/SIGTERM, a killed recorder.

Each must give a short message naming the problem and a non-zero exit status, leave no
process behind, and (once recording started) leave a bag readers can open.
"""

from __future__ import annotations

import json
import os
import signal
import time
from pathlib import Path

import pytest
from mcap.reader import NonSeekingReader
from mcap.reader import SeekingReader
from mcap.reader import make_reader

from tether_bringup.bag_reader import read_bag

from tethersim_testing import processes_of
from tethersim_testing import start_tethersim
from tethersim_testing import tethersim

NODES = Path(__file__).resolve().parent / 'nodes'
TALKER = f'  talker:\n    script: {NODES / "talker_double.py"}\n'

BAD_SCENES = [
    ('unknown top-level key', f'description: x\ndurration: 5\nnodes:\n{TALKER}', 'durration: unknown key'),
    ('wrong type', f'description: x\nduration: fast\nnodes:\n{TALKER}', "duration: expected a number"),
    ('out of range', f'description: x\nrate: -1\nnodes:\n{TALKER}', 'rate: expected a number in [0.001, 1000]'),
    ('missing description', f'nodes:\n{TALKER}', 'description: missing'),
    ('no nodes', 'description: x\nnodes: {}\n', 'nodes: expected a mapping'),
    ('missing script', 'description: x\nnodes:\n  talker:\n    script: nowhere.py\n', 'nodes.talker.script: file not found'),
    ('unknown node key', f'description: x\nnodes:\n{TALKER}    params: {{}}\n', 'nodes.talker.params: unknown key'),
    ('invalid yaml', 'description: [x\nnodes: 3\n', 'not valid YAML'),
    ('unknown package', 'description: x\nnodes:\n  a:\n    package: no_such_pkg\n    executable: b\n',
     "nodes.a.package: package 'no_such_pkg' is not installed"),
    ('unknown executable', 'description: x\nnodes:\n  a:\n    package: tether_bringup\n    executable: nope\n',
     "nodes.a.executable: package tether_bringup has no executable 'nope'"),
    ('unknown parameter', 'description: x\nnodes:\n  rec:\n    package: tether_bringup\n    executable: recorder\n'
     '    parameters: {bogus: 1}\n', 'nodes.rec.parameters.bogus: unknown parameter of tether_bringup/recorder'),
    ('parameter out of range', 'description: x\nnodes:\n  rec:\n    package: tether_bringup\n    executable: recorder\n'
     '    parameters: {flush_period: 100}\n', 'nodes.rec.parameters.flush_period: expected a number in [0.05, 10] (s)'),
    ('unknown choice', 'description: x\nnodes:\n  platform:\n    package: psr_platform_sim\n    executable: platform\n'
     '    parameters: {profile: hpr9}\n', 'nodes.platform.parameters.profile: expected a string from {jonswap, boat, '
     "hpr1, hpr2, hpr3, still, workspace} or an existing .csv file, got 'hpr9'"),
    ('missing parameter file', 'description: x\nnodes:\n  platform:\n    package: psr_platform_sim\n'
     '    executable: platform\n    parameters: {profile: /no/such/heave.csv}\n',
     'nodes.platform.parameters.profile: file not found: /no/such/heave.csv'),
    ('vector of the wrong length', 'description: x\nnodes:\n  plant:\n    package: tether_dynamics\n'
     '    executable: plant\n    parameters: {uav_position: [3.22, 0.0]}\n',
     'nodes.plant.parameters.uav_position: expected a list of 3 numbers (m), got 2: [3.22, 0.0]'),
]

UNREADABLE_SCENES = [
    ('binary garbage', bytes(range(256)) * 4, 'not a UTF-8 text file (byte 128 is 0x80); a scene is YAML in UTF-8'),
    ('Latin-1 text', f'description: caf\u00e9\nnodes:\n{TALKER}'.encode('latin-1'),
     'not a UTF-8 text file (byte 16 is 0xe9); a scene is YAML in UTF-8'),
]


@pytest.mark.parametrize('text, expected', [(t, e) for _, t, e in BAD_SCENES], ids=[n for n, _, _ in BAD_SCENES])
def test_bad_scene_gives_one_line_and_status_2(scene_file, tmp_path, text, expected):
    path = scene_file(text)
    result = tethersim('run', str(path), '--out', str(tmp_path / 'out'), timeout=60)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith(f'tethersim: error: {path}: '), lines[0]
    assert expected in lines[0]
    assert not (tmp_path / 'out').exists()


@pytest.mark.parametrize('content, expected', [(c, e) for _, c, e in UNREADABLE_SCENES],
                         ids=[n for n, _, _ in UNREADABLE_SCENES])
def test_scene_that_is_not_utf8_gives_one_line_and_status_2(tmp_path, content, expected):
    path = tmp_path / 'scene.yaml'
    path.write_bytes(content)
    result = tethersim('run', str(path), '--out', str(tmp_path / 'out'), timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [f'tethersim: error: {path}: {expected}']
    assert not (tmp_path / 'out').exists()


def test_directory_given_as_the_scene_is_named_as_one(tmp_path):
    result = tethersim('run', str(tmp_path), '--out', str(tmp_path / 'out'), timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [
        f'tethersim: error: {tmp_path}: a directory, not a scene file (give a scene name or a YAML file)']


def test_missing_scene_name_lists_installed_scenes():
    result = tethersim('run', 'no_such_scene', timeout=60)
    assert result.returncode == 2
    assert result.stderr.startswith('tethersim: error: no_such_scene: no such scene (installed scenes:')
    assert 'Traceback' not in result.stderr


def test_bad_command_line_values_give_one_line(tmp_path):
    result = tethersim('run', 'default', '--rate', '-3', timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == ["tethersim run: error: argument --rate: expected a positive number, got '-3'"]
    missing = tethersim('bag', 'info', str(tmp_path / 'nothing.mcap'), timeout=60)
    assert missing.returncode == 2
    assert missing.stderr.strip() == f'tethersim: error: {tmp_path / "nothing.mcap"}: no such bag'
    garbage = tmp_path / 'garbage.mcap'
    garbage.write_bytes(b'not an mcap file at all' * 10)
    malformed = tethersim('bag', 'info', str(garbage), timeout=60)
    assert malformed.returncode == 2
    assert malformed.stderr.startswith(f'tethersim: error: {garbage}: not an MCAP file (it does not begin with the MCAP magic bytes)')
    assert len(malformed.stderr.strip().splitlines()) == 1


def test_crashing_node_stops_the_run_and_the_bag_is_finalized(scene_file, tmp_path):
    path = scene_file('description: the talker dies at 1 s\nduration: 20\nrate: 2\nnodes:\n' + TALKER +
                      '    parameters: {crash_at: 1.0}\n'
                      f'  listener:\n    script: {NODES / "listener_double.py"}\n')
    out = tmp_path / 'out'
    result = tethersim('run', str(path), '--out', str(out), timeout=120)
    assert result.returncode == 1
    assert 'tethersim: error: node talker died with exit status 3' in result.stderr
    assert 'crashing on purpose' in result.stderr
    assert 'Traceback' not in result.stderr
    bag = read_bag(out)
    assert bag.complete
    recorded = {topic: entry.count for topic, entry in bag.topics.items()}
    assert recorded.get('/test/estimate', 0) >= 40, (recorded, (out / 'recorder.ready').read_text())
    assert not processes_of(out)


def test_a_node_of_the_group_that_cannot_start_is_named_and_the_bag_is_finalized(scene_file, tmp_path):
    profile = tmp_path / 'heave.csv'
    profile.write_text('not,a,profile\n1,2\n')
    path = scene_file('description: the platform cannot read its profile\nduration: 5\nnodes:\n'
                      f'  platform:\n    package: psr_platform_sim\n    executable: platform\n'
                      f'    parameters: {{profile: {profile}}}\n'
                      '  plant:\n    package: tether_dynamics\n    executable: plant\n')
    out = tmp_path / 'out'
    result = tethersim('run', str(path), '--out', str(out), timeout=120)
    assert result.returncode == 1
    assert 'tethersim: error: node group nodes (platform, plant) died with exit status 2' in result.stderr
    assert f'platform: error: {profile}: first line must be the header' in result.stderr
    assert 'Traceback' not in result.stderr
    assert read_bag(out).complete
    assert not processes_of(out)


@pytest.mark.parametrize('signum, status', [(signal.SIGINT, 130), (signal.SIGTERM, 143)], ids=['SIGINT', 'SIGTERM'])
def test_signal_to_bringup_finalizes_bag_and_leaves_no_process(scene_file, tmp_path, signum, status):
    sent_log = tmp_path / 'sent.jsonl'
    path = scene_file('description: long run to be interrupted\nduration: 600\nrate: 1\nnodes:\n' + TALKER +
                      f'    parameters: {{sent_log: {sent_log}}}\n'
                      f'  listener:\n    script: {NODES / "listener_double.py"}\n')
    out = tmp_path / 'out'
    bringup = start_tethersim('run', str(path), '--out', str(out))
    _wait_for_lines(sent_log, 100, bringup)
    assert len([p for p in processes_of(out) if p.pid != bringup.pid]) == 3
    bringup.send_signal(signum)
    stdout, stderr = bringup.communicate(timeout=60)
    assert bringup.returncode == status, stderr
    assert f'interrupted by {signal.Signals(signum).name}' in stderr
    bag = read_bag(out)
    assert bag.complete
    assert bag.topics['/test/estimate'].count >= 50
    assert not processes_of(out)


def test_killed_recorder_loses_at_most_about_a_second_and_the_bag_is_recovered(scene_file, tmp_path):
    sent_log = tmp_path / 'sent.jsonl'
    path = scene_file('description: the recorder is killed\nduration: 600\nrate: 1\nnodes:\n' + TALKER +
                      f'    parameters: {{sent_log: {sent_log}}}\n')
    out = tmp_path / 'out'
    bringup = start_tethersim('run', str(path), '--out', str(out))
    _wait_for_lines(sent_log, 300, bringup)
    recorder = next(p for p in processes_of(out) if p.pid != bringup.pid and p.name() == 'recorder')
    recorder.send_signal(signal.SIGKILL)
    stdout, stderr = bringup.communicate(timeout=60)
    sent_lines = sent_log.read_text().splitlines()
    assert bringup.returncode == 1
    assert 'node recorder died with exit status -9' in stderr
    assert not processes_of(out)
    damaged = out / 'bag' / 'bag_0.mcap.damaged'
    with open(damaged, 'rb') as stream:
        stamps = []
        try:
            for _, channel, message in NonSeekingReader(stream).iter_messages(log_time_order=False):
                if channel.topic == '/test/estimate':
                    stamps.append(message.log_time)
        except Exception:  # the file ends inside an unfinished chunk: everything before it was read
            pass
    assert not read_bag(damaged, allow_damaged=True).complete
    bag = read_bag(out)
    assert bag.complete
    summary = (out / 'summary.txt').read_text()
    assert 'bag verification FAILED: damaged at byte ' in summary and 'recovered ' in summary
    assert len(stamps) == bag.topics['/test/estimate'].count > 0
    with open(bag.path, 'rb') as stream:
        indexed = make_reader(stream)
        assert isinstance(indexed, SeekingReader)
        assert indexed.get_summary().statistics.channel_message_counts
        assert sum(1 for _ in indexed.iter_messages(topics=['/test/estimate'])) == len(stamps)
    sent_before_kill = [json.loads(line)['stamp'] for line in sent_lines if '/test/estimate' in line]
    assert max(stamps) / 1e9 >= max(sent_before_kill) / 1e9 - 1.6


def _wait_for_lines(path: Path, count: int, process, timeout: float = 90.0) -> None:
    """Wait until the talker has logged ``count`` sent messages (sim time is running)."""
    deadline = time.monotonic() + timeout
    while not path.exists() or len(path.read_text().splitlines()) < count:
        assert process.poll() is None, process.communicate()[1]
        assert time.monotonic() < deadline, f'{path} did not reach {count} lines'
        time.sleep(0.1)


def test_existing_run_directory_is_not_overwritten(scene_file, tmp_path):
    out = tmp_path / 'out'
    (out / 'bag').mkdir(parents=True)
    (out / 'bag' / 'bag_0.mcap').write_bytes(b'earlier recording')
    path = scene_file(f'description: x\nnodes:\n{TALKER}')
    result = tethersim('run', str(path), '--out', str(out), timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip() == f'tethersim: error: {out}: this run directory already holds a bag; give another --out'
    assert (out / 'bag' / 'bag_0.mcap').read_bytes() == b'earlier recording'


def test_a_run_says_its_bag_is_verified(scene_file, tmp_path):
    path = scene_file(f'description: a short run\nduration: 2\nrate: 4\nnodes:\n{TALKER}')
    out = tmp_path / 'out'
    result = tethersim('run', str(path), '--out', str(out), timeout=120)
    assert result.returncode == 0, result.stderr
    bag = read_bag(out)
    assert bag.crcs == {'chunk', 'data section', 'summary'}
    assert (f'bag verified: {bag.chunks} chunks and {len(bag.messages)} messages read, every chunk\'s CRC, the '
            'data section\'s CRC, the summary\'s CRC checked') in result.stdout.splitlines()
    assert bag.chunks >= 2


def test_node_dying_with_an_empty_log_says_the_log_is_empty(scene_file, tmp_path):
    path = scene_file(f'description: a node that dies silently\nduration: 5\nnodes:\n{TALKER}'
                      f'  silent:\n    script: {NODES / "silent_crash_double.py"}\n')
    out = tmp_path / 'out'
    result = tethersim('run', str(path), '--out', str(out), timeout=120)
    assert result.returncode == 1
    log = out / 'logs' / 'silent.log'
    assert result.stderr.strip().splitlines()[-1] == (
        f'tethersim: error: node silent died with exit status 3; its log {log} is empty (it wrote nothing before '
        'it ended)')
    assert not processes_of(out)


def test_sigterm_while_reporting_still_writes_the_summary_and_plots(scene_file, tmp_path):
    started = tmp_path / 'report.started'
    path = scene_file(f'description: a run whose second report is slow\nduration: 2\nrate: 4\nnodes:\n{TALKER}'
                      'reports:\n  - report_doubles:plot_report\n  - report_doubles:slow_report\n'
                      '  - report_doubles:plot_report\n')
    out = tmp_path / 'out'
    environment = {**os.environ, 'SLOW_REPORT_STARTED': str(started),
                   'PYTHONPATH': os.pathsep.join([str(NODES), os.environ.get('PYTHONPATH', '')])}
    bringup = start_tethersim('run', str(path), '--out', str(out), env=environment)
    deadline = time.monotonic() + 120
    while not started.exists():
        assert bringup.poll() is None, bringup.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.05)
    bringup.send_signal(signal.SIGTERM)
    stdout, stderr = bringup.communicate(timeout=60)
    assert bringup.returncode == 143, stderr
    assert 'Traceback' not in stderr
    summary = (out / 'summary.txt').read_text().splitlines()
    assert summary == stdout.splitlines()
    assert 'plot report: done' in summary
    assert ('report report_doubles:slow_report interrupted by SIGTERM; not run: report_doubles:plot_report'
            in summary)
    assert 'interrupted by SIGTERM while running the reports: the lines above are all the reports did' in summary
    assert summary[-1] == f'plot: {out / "plot_report.png"}'
    assert not processes_of(out)


def test_replaying_a_topic_the_scene_publishes_too_is_refused(scene_file, tmp_path):
    """Two sources of /platform/imu (the bag and the scene's platform node) would reach the nodes at once."""
    path = scene_file('description: the platform node, which publishes /platform/imu\nnodes:\n'
                      '  platform:\n    package: psr_platform_sim\n    executable: platform\n'
                      f'    parameters: {{table_steps: 60, profile_duration: 2.0, profile: still, cache_dir: {tmp_path}}}\n')
    out = tmp_path / 'out'
    result = tethersim('replay', str(Path(__file__).resolve().parent.parent / 'bags' / 'platform-hpr3-10s'),
                       '--topics', '/platform/imu', '--scene', str(path), '--rate', 'max', '--out', str(out),
                       timeout=180)
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip().splitlines()[-1] == (
        "tethersim: error: replayed topic(s) published by the scene's own nodes too, refused (two sources of one "
        'topic): /platform/imu by platform')
    assert 'Traceback' not in result.stderr
    assert not processes_of(out)
