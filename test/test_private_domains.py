"""Private ROS domains: runs started at once on one machine never see each other's topics.

A run without ``--domain-id`` reserves its domain with ``domain_coordinator`` (the allocator
launch_testing uses) for as long as it lasts; a second run, a second copy of this test
suite or a launch test gets another one.
"""

from __future__ import annotations

import re
import socket
import time
from pathlib import Path

import domain_coordinator
import yaml

from tether_bringup.bag_reader import read_bag
from tether_bringup.environment import reserved_domain

from tethersim_testing import SCENES
from tethersim_testing import processes_of
from tethersim_testing import start_tethersim
from tethersim_testing import tethersim
from tethersim_testing import write_scene

PORT_BASE = 32768
NODES = Path(__file__).resolve().parent / 'nodes'


def _held(domain: int) -> bool:
    """True if some process holds the coordinator's port of ``domain``."""
    probe = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    try:
        probe.bind(('', PORT_BASE + domain))
    except OSError:
        return True
    finally:
        probe.close()
    return False


def test_reserved_domains_are_distinct_held_and_released():
    with domain_coordinator.domain_id() as elsewhere:
        with reserved_domain(None) as first, reserved_domain(None) as second:
            assert len({elsewhere, first, second}) == 3
            assert 1 <= first <= 100 and 1 <= second <= 100
            assert _held(first) and _held(second)
        assert not _held(first) and not _held(second)
    with reserved_domain(7) as given:
        assert given == 7


def test_domain_zero_is_refused_in_one_line():
    result = tethersim('run', 'default', '--domain-id', '0', timeout=60)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [
        'tethersim run: error: argument --domain-id: expected a ROS domain id in [1, 232], got 0: ROS\'s default '
        'domain, which every ROS 2 process on the network that sets none joins']


def test_error_inside_a_reservation_is_raised_as_itself():
    try:
        with reserved_domain(None):
            raise FileNotFoundError('no such run directory')
    except FileNotFoundError as error:
        assert str(error) == 'no such run directory'
    else:
        raise AssertionError('the error was swallowed')


def _domain_of(stderr_path: Path, process, timeout: float = 120.0) -> int:
    deadline = time.monotonic() + timeout
    while True:
        match = re.search(r'ROS_DOMAIN_ID=(\d+)', stderr_path.read_text() if stderr_path.exists() else '')
        if match:
            return int(match.group(1))
        assert process.poll() is None, stderr_path.read_text()
        assert time.monotonic() < deadline, f'{stderr_path}: no domain announced'
        time.sleep(0.05)


def test_two_runs_at_once_get_their_own_domains_and_no_cross_talk(tmp_path):
    """Two runs of the same topics at different rates: each bag holds only its own talker."""
    runs = {}
    for name, rate in (('a', 50.0), ('b', 20.0)):
        scene = yaml.safe_load((SCENES / 'talk_listen.yaml').read_text())
        scene['duration'] = 3.0
        scene['rate'] = 1.0
        scene['nodes']['talker']['script'] = str(NODES / 'talker_double.py')
        scene['nodes']['listener']['script'] = str(NODES / 'listener_double.py')
        scene['nodes']['talker']['parameters'] = {'rate': rate, 'sent_log': str(tmp_path / f'sent-{name}.jsonl')}
        scene['nodes']['listener']['parameters'] = {'period': 1.0 / rate, 'estimate_period': 1.0 / rate}
        scene_path = write_scene(scene, tmp_path / f'scene-{name}.yaml')
        stderr_path = tmp_path / f'stderr-{name}.txt'
        with open(stderr_path, 'w') as stderr:
            process = start_tethersim('run', scene_path, '--out', str(tmp_path / name),
                                      stdout=open(tmp_path / f'stdout-{name}.txt', 'w'), stderr=stderr)
        runs[name] = (process, stderr_path)
    domains = {}
    for name, (process, stderr_path) in runs.items():
        domains[name] = _domain_of(stderr_path, process)
        if process.poll() is None:
            assert _held(domains[name]), f'run {name} does not hold its domain {domains[name]}'
    for process, _ in runs.values():
        process.wait(timeout=240)
    assert domains['a'] != domains['b']
    for name, (process, stderr_path) in runs.items():
        assert process.returncode == 0, stderr_path.read_text()
        # the reservation ends with the run: none of its processes is left to hold the port (the
        # domain itself may already be another test's, when two copies of the suite run at once)
        assert not processes_of(tmp_path / name)
        bag = read_bag(tmp_path / name)
        sent = (tmp_path / f'sent-{name}.jsonl').read_text().count('/test/estimate')
        assert bag.topics['/test/estimate'].count == sent
        assert bag.topics['/test/echo'].count == sent
    assert read_bag(tmp_path / 'a').topics['/test/estimate'].count == 150
    assert read_bag(tmp_path / 'b').topics['/test/estimate'].count == 60
