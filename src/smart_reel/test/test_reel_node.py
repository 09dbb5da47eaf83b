"""The reel node on sim time against a test-double plant: stamped inputs in, payout commands out."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest

rclpy = pytest.importorskip('rclpy')

from rosgraph_msgs.msg import Clock  # noqa: E402
from tether_msgs.msg import ReelCommand  # noqa: E402
from tether_msgs.msg import ReelControllerDiagnostics  # noqa: E402
from tether_msgs.msg import ReelState  # noqa: E402
from tether_msgs.msg import RelativePosition  # noqa: E402
from tether_msgs.msg import TetherState  # noqa: E402

from tether_common.qos import STATE  # noqa: E402
from tether_dynamics.statics.reference_length import reference_length  # noqa: E402


pytestmark = pytest.mark.usefixtures('ros_domain')


def _start(*extra):
    cmd = [sys.executable, '-m', 'smart_reel.reel_node', '--ros-args', '-p', 'use_sim_time:=true', *extra]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _stamp(msg, ns: int) -> None:
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(ns, 1_000_000_000)


def _ns(msg) -> int:
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def test_reel_node_pays_out_as_the_uav_rises():
    process = _start('-p', f'initial_length:={reference_length(3.22, 7.0).length}')
    rclpy.init()
    node = rclpy.create_node('plant_test_double')
    got = {'command': [], 'state': [], 'diagnostics': []}
    node.create_subscription(ReelCommand, '/reel/command', got['command'].append, STATE)
    node.create_subscription(ReelState, '/reel/state', got['state'].append, STATE)
    node.create_subscription(ReelControllerDiagnostics, '/reel/diagnostics', got['diagnostics'].append, STATE)
    clock = node.create_publisher(Clock, '/clock', 10)
    tether = node.create_publisher(TetherState, '/tether/state', STATE)
    relative = node.create_publisher(RelativePosition, '/truth/relative', STATE)
    dz_of = {}
    length = reference_length(3.22, 7.0).length  # the test double integrates every commanded payout, as the plant does
    applied = 0
    try:
        sim_ns = 0
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and (node.count_subscribers('/tether/state') == 0
                                               or node.count_publishers('/reel/diagnostics') == 0):
            rclpy.spin_once(node, timeout_sec=0.05)
        while time.monotonic() < deadline and sim_ns < 3_000_000_000:
            sim_ns += 10_000_000
            dz = 7.0 + 0.3 * sim_ns * 1e-9  # the UAV rises at 0.3 m/s
            dz_of[sim_ns] = dz
            rel = RelativePosition()
            _stamp(rel, sim_ns)
            rel.position.x, rel.position.z, rel.velocity.z = 3.22, dz, 0.3
            relative.publish(rel)
            state = TetherState()
            _stamp(state, sim_ns)
            length += sum(m.payout_rate for m in got['command'][applied:]) * 0.01
            applied = len(got['command'])
            state.deployed_length = length
            state.tension_reel, state.departure_angle = 0.6, 0.2
            state.clearance_deck, state.clearance_sea = 0.0, 3.0
            tether.publish(state)
            msg = Clock()
            msg.clock.sec, msg.clock.nanosec = divmod(sim_ns, 1_000_000_000)
            clock.publish(msg)
            for _ in range(8):  # take every message the reel sent for this tick
                rclpy.spin_once(node, timeout_sec=0.002)
            assert process.poll() is None, process.communicate()[1]
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=20)
        node.destroy_node()
        rclpy.shutdown()
    assert process.returncode == 0
    assert len(got['diagnostics']) >= 50
    commands = got['command']
    assert all(_ns(m) % 10_000_000 == 0 for m in commands)
    assert all(m.control == ReelCommand.CONTROL_PAYOUT_RATE for m in commands)
    assert all(_ns(m) % 20_000_000 == 0 for m in got['state'])
    assert got['state'][-1].mode == ReelState.MODE_CATENARY
    late = [m.payout_rate for m in got['state'][-20:]]
    assert sum(late) / len(late) == pytest.approx(0.3, abs=0.05)
    commanded = [m.payout_rate for m in commands[-50:]]
    assert sum(commanded) / len(commanded) == pytest.approx(0.3, abs=0.1)
    assert abs(length - got['state'][-1].deployed_length) < 0.05
    # the reference of tick t comes from the relative position stamped t - input_delay (10 ms)
    d = got['diagnostics'][-1]
    used = dz_of[_ns(d) - 10_000_000]
    assert d.relative_height == pytest.approx(used)
    assert d.reference_length == pytest.approx(reference_length(3.22, used).length)
    assert d.safety_trip == '' and d.trip_count == 0


def test_bad_parameter_is_one_line_exit_2():
    process = _start('-p', 'controller:=sloppy')
    _, err = process.communicate(timeout=30)
    assert process.returncode == 2
    assert 'controller' in err and 'Traceback' not in err


def test_a_safety_trip_is_published_with_its_reason_and_logged():
    """The taut controller's reel-in torque reads as ~30 N of tension; a 5 N limit trips it."""
    process = _start('-p', 'controller:=taut', '-p', 'max_tension:=5.0', '-p', 'initial_length:=8.0')
    rclpy.init()
    node = rclpy.create_node('mission_test_double')
    states, diagnostics = [], []
    node.create_subscription(ReelState, '/reel/state', states.append, STATE)
    node.create_subscription(ReelControllerDiagnostics, '/reel/diagnostics', diagnostics.append, STATE)
    clock = node.create_publisher(Clock, '/clock', 10)
    tether = node.create_publisher(TetherState, '/tether/state', STATE)
    relative = node.create_publisher(RelativePosition, '/truth/relative', STATE)
    try:
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and (node.count_subscribers('/tether/state') == 0
                                               or node.count_publishers('/reel/diagnostics') == 0):
            rclpy.spin_once(node, timeout_sec=0.05)
        sim_ns = 0
        while time.monotonic() < deadline and sim_ns < 1_000_000_000:
            sim_ns += 10_000_000
            rel = RelativePosition()
            _stamp(rel, sim_ns)
            rel.position.x, rel.position.z = 3.22, 7.0
            relative.publish(rel)
            state = TetherState()
            _stamp(state, sim_ns)
            state.deployed_length, state.tension_reel, state.departure_angle = 8.0, 20.0, 0.2
            state.clearance_deck, state.clearance_sea = 0.0, 3.0
            tether.publish(state)
            msg = Clock()
            msg.clock.sec, msg.clock.nanosec = divmod(sim_ns, 1_000_000_000)
            clock.publish(msg)
            for _ in range(8):
                rclpy.spin_once(node, timeout_sec=0.002)
    finally:
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=20)
        node.destroy_node()
        rclpy.shutdown()
    assert process.returncode == 0
    tripped = [d for d in diagnostics if d.safety_trip]
    assert tripped and all(d.safety_trip.startswith('reel-in stopped: tension') for d in tripped)
    assert diagnostics[-1].trip_count >= 1
    stamps = {_ns(d) for d in tripped}
    assert {_ns(s) for s in states if s.mode == ReelState.MODE_FAULT} == stamps
    assert 'safety trip 1 at' in err and 'reel-in stopped' in err
