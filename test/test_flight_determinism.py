"""A flight with the built-in UAV is reproducible: the mission and the UAV act on stamped inputs (lockstep).

A shortened ``outdoor_flight`` (the UAV disarmed on a pad 2 m below the station, so the
mission arms it, takes off, climbs, holds, returns over a pad 1 m nearer the boat and lands,
the landing starting ``land_before_end`` before the end) is
run twice at ``--rate max``, the second time with every core kept busy by other processes.
Every topic must record the same messages, field by field and in order, at the same log
times; and each request the mission sends on ``/uav/command`` must be carried out one
mission period later, by the ``/uav/state`` stamped there.
"""

from __future__ import annotations

import numpy as np
import pytest

from tether_bringup.bag_reader import read_bag
from tether_common.lockstep import stamp_ns

from tethersim_testing import bag_contents
from tethersim_testing import busy_cores
from tethersim_testing import tethersim
from tethersim_testing import installed_scene
from tethersim_testing import write_scene

pytestmark = pytest.mark.long_run

DURATION = 6.0
"""s of sim time: arm at 0.1 s, take off at 0.2 s, the 2 m climb, hold, the return from 3.5 s, the descent."""
LAND_BEFORE_END = 2.5
PAD = [14.0, 0.0]
"""m: the pad the UAV returns over, 1 m from the station (15 m radial)."""
RETURN_SPEED = 2.0
MISSION_PERIOD_NS = 100_000_000
"""The mission's step (rate 10 Hz): the built-in UAV's delay on /uav/command."""


def short_flight(directory) -> str:
    """``outdoor_flight`` for ``DURATION`` s, the UAV at rest on level ground 28 m up, returning at the hold
    altitude and landing before the end, no report.
    """
    scene = installed_scene('outdoor_flight')
    scene['duration'] = DURATION
    scene['reports'] = []
    scene['nodes']['uav']['parameters'].update(start=[15.0, 0.0, 28.0], start_height=0.0, ground='level')
    scene['nodes']['mission']['parameters'].update(land_before_end=LAND_BEFORE_END, pad=PAD,
                                                   return_speed=RETURN_SPEED, return_height=0.0)
    return write_scene(scene, directory / 'short_flight.yaml')


@pytest.fixture(scope='module')
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp('flight')
    scene = short_flight(base)
    outs = {'max': base / 'max', 'max, cores busy': base / 'loaded'}
    for name, out in outs.items():
        if name == 'max':
            result = tethersim('run', scene, '--rate', 'max', '--out', str(out), timeout=600)
        else:
            with busy_cores():
                result = tethersim('run', scene, '--rate', 'max', '--out', str(out), timeout=600)
        assert result.returncode == 0, result.stderr[-3000:]
    return outs


def test_the_flight_records_the_same_payloads_with_every_core_busy(runs):
    reference, recorded = (bag_contents(out) for out in runs.values())
    assert set(recorded) == set(reference)
    assert set(reference) >= {'/uav/command', '/uav/state', '/uav/pose', '/mission/state', '/tether/state',
                              '/reel/state', '/estimate/relative'}
    for topic, messages in reference.items():
        assert recorded[topic] == messages, topic


def test_each_request_is_carried_out_one_mission_period_later(runs):
    bag = read_bag(runs['max'] / 'bag')
    commands = [m for _, m in bag.decoded('/uav/command')]
    assert [stamp_ns(m.header.stamp) for m in commands] == [
        k * MISSION_PERIOD_NS for k in range(1, round(DURATION * 10) + 1)]
    sent = {}
    for m in commands:
        sent.setdefault(m.sequence, (stamp_ns(m.header.stamp), m.request))
    assert [request for _, request in sent.values()] == ['arm', 'takeoff', 'land']
    states = [(stamp_ns(m.header.stamp), m) for _, m in bag.decoded('/uav/state')]
    for sequence, (stamp, request) in sent.items():
        done = next(t for t, m in states if m.command_sequence == sequence)
        assert done == stamp + MISSION_PERIOD_NS, request
        assert next(m for t, m in states if t == done).command_success, request
    phases = [(stamp_ns(m.header.stamp), m.phase) for _, m in bag.decoded('/mission/state')]
    assert [phase for _, phase in phases] == ['arm', 'takeoff', 'climb', 'hold', 'return', 'land']
    returning, landing = phases[-2][0], phases[-1][0]
    assert returning == round((DURATION - LAND_BEFORE_END) * 1e9)
    path = np.array([[m.setpoint.x, m.setpoint.y, m.setpoint.z] for m in commands
                     if returning <= stamp_ns(m.header.stamp) < landing])
    assert all(m.hold for m in commands if returning <= stamp_ns(m.header.stamp) < landing)
    np.testing.assert_allclose(path[0], [15.0, 0.0, 30.0])                      # from the station
    np.testing.assert_allclose(path[-1], PAD + [30.0])                          # over the pad, hold altitude
    assert np.linalg.norm(np.diff(path, axis=0), axis=1).max() <= RETURN_SPEED * MISSION_PERIOD_NS / 1e9 + 1e-9
    assert not any(m.hold for m in commands if stamp_ns(m.header.stamp) >= landing)
