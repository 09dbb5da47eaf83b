"""Deterministic lockstep: a closed loop records the same payloads at any rate and under load.

The plant double and the controller double (test/nodes) form a cycle: the controller
reads the plant's state of its own tick (delay 0), the plant reads the command with a
delay of one controller period. Both draw seeded random numbers every tick. The scene is
run at rate 1, at rate 20, and at rate max with every core kept busy by other processes;
the three bags must hold byte-identical messages, topic by topic and in order, each
logged at its own stamp.
"""

from __future__ import annotations

import pytest
from geometry_msgs.msg import PointStamped
from geometry_msgs.msg import Vector3Stamped
from rclpy.serialization import deserialize_message

from tether_common.lockstep import stamp_ns

from tethersim_testing import SCENES
from tethersim_testing import bag_payloads
from tethersim_testing import busy_cores
from tethersim_testing import tethersim

SCENE = SCENES / 'closed_loop.yaml'
NS = 1_000_000_000


def _run(out, *args):
    result = tethersim('run', str(SCENE), '--out', str(out), *args, timeout=300)
    assert result.returncode == 0, result.stderr
    return bag_payloads(out)


@pytest.fixture(scope='module')
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp('lockstep')
    recorded = {'rate 1': _run(base / 'rate1', '--rate', '1'), 'rate 20': _run(base / 'rate20', '--rate', '20')}
    with busy_cores():
        recorded['max, cores busy'] = _run(base / 'loaded', '--rate', 'max')
    return recorded


def test_payloads_are_identical_topic_by_topic_and_in_order(runs):
    reference = runs['rate 1']
    assert set(reference) == {'/clock', '/test/plant_state', '/test/command'}
    assert len(reference['/test/plant_state']) == 200 and len(reference['/test/command']) == 100
    for name, recorded in runs.items():
        assert set(recorded) == set(reference), name
        for topic in reference:
            assert [data for data, _ in recorded[topic]] == [data for data, _ in reference[topic]], (name, topic)


def test_each_message_is_logged_at_its_stamp(runs):
    for recorded in runs.values():
        for topic, messages in recorded.items():
            stamps = [log_time for _, log_time in messages]
            assert stamps == sorted(stamps), topic
        assert [t for _, t in recorded['/test/plant_state']] == [k * NS // 100 for k in range(1, 201)]
        assert [t for _, t in recorded['/test/command']] == [k * NS // 50 for k in range(1, 101)]
        assert [t for _, t in recorded['/clock']] == [k * NS // 100 for k in range(1, 201)]


def test_the_loop_is_closed_with_the_declared_delays(runs):
    """Commands use the state of their own tick; the plant uses the command one controller period old."""
    recorded = runs['rate 20']
    states = [deserialize_message(data, PointStamped) for data, _ in recorded['/test/plant_state']]
    commands = [deserialize_message(data, Vector3Stamped) for data, _ in recorded['/test/command']]
    assert [c.vector.z for c in commands] == [(k * NS // 50) * 1e-9 for k in range(1, 101)]
    by_stamp = {stamp_ns(c.header.stamp): c.vector.x for c in commands}
    x, v, dt = 1.0, 0.0, 0.01
    for k, state in enumerate(states, start=1):
        bound = k * NS // 100 - NS // 50
        used = max((stamp for stamp in by_stamp if stamp <= bound), default=None)
        u = by_stamp[used] if used is not None else 0.0
        v += dt * (u - 4.0 * x - 0.2 * v + state.point.z)
        x += dt * v
        assert (state.point.x, state.point.y) == (x, v), k
    assert abs(states[-1].point.x) < 0.2 < abs(states[0].point.x)
