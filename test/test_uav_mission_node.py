"""The mission node flying the ArduCopter test double through the bridge: hold station, abort on a reel trip."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

rclpy = pytest.importorskip('rclpy')

from rclpy.clock import Clock as RosClock  # noqa: E402
from rclpy.clock import ClockType  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from tether_msgs.msg import MissionState  # noqa: E402
from tether_msgs.msg import ReelState  # noqa: E402

from mavlink_peer_double import ArduCopterPeerDouble  # noqa: E402
from tether_common.qos import CLOCK  # noqa: E402
from tether_common.qos import LATCHED  # noqa: E402
from tether_common.qos import STATE  # noqa: E402
from test_uav_bridge_node import Probe  # noqa: E402
from test_uav_bridge_node import ros_domain  # noqa: E402,F401 - fixture
from test_uav_bridge_peer import wait_until  # noqa: E402


def _start(module, *params, domain, env=None):
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), **(env or {}))
    args = [arg for param in ('use_sim_time:=true', *params) for arg in ('-p', param)]
    return subprocess.Popen([sys.executable, '-m', module, '--ros-args', *args], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def stop_nodes(processes) -> list[tuple[int, str]]:
    """SIGINT each node process and return its (exit status, stderr)."""
    stopped = []
    for process in processes:
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=20)
        stopped.append((process.returncode, err))
    return stopped


def assert_clean_exits(stopped) -> None:
    """Every node ended with status 0 and no traceback."""
    for status, err in stopped:
        assert status == 0 and 'Traceback' not in err, err


def publish_clock(probe) -> None:
    """Drive ``/clock`` from the probe at wall speed in 10 ms steps, as the bringup's time master would.

    The mission and the built-in UAV tick in lockstep on ``/clock``; outside a run no barrier
    holds them, so the clock only has to advance.
    """
    clock = probe.node.create_publisher(Clock, '/clock', CLOCK)
    start = time.monotonic()

    def tick() -> None:
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = divmod(int((time.monotonic() - start) * 100) * 10_000_000, 1_000_000_000)
        clock.publish(msg)
    probe.node.create_timer(0.01, tick, clock=RosClock(clock_type=ClockType.STEADY_TIME))


def _position(pose) -> tuple[float, float, float]:
    p = pose.pose.position
    return p.x, p.y, p.z


def test_mission_holds_station_and_on_a_reel_trip_returns_over_the_pad_and_lands_there(ros_domain):  # noqa: F811
    peer = ArduCopterPeerDouble(speedup=5.0, ekf_delay=20.0).start()
    processes = [
        _start('uav_bridge.mavlink.bridge_node', f'url:=tcp:127.0.0.1:{peer.port}', 'pose_rate:=20.0', 'imu_rate:=5.0',
               'global_rate:=1.0', 'link_timeout:=1.0', domain=ros_domain),
        _start('uav_bridge.mission.node', 'altitude:=5.0', 'radial:=2.5', 'bearing:=90.0', 'retry_period:=0.5',
               'uav_link:=services', 'return_speed:=1.0', 'return_height:=2.0', 'pad:=[0.0, 0.5]',
               domain=ros_domain)]
    probe = Probe()
    publish_clock(probe)
    phases = []
    probe.node.create_subscription(MissionState, '/mission/state', phases.append, LATCHED)
    reel = probe.node.create_publisher(ReelState, '/reel/state', STATE)
    try:
        wait_until(lambda: phases and phases[-1].phase == 'hold', timeout=90, what='the hold phase')
        assert [p.phase for p in phases][:2] == ['wait', 'guided']
        assert {'arm', 'takeoff', 'climb'} <= {p.phase for p in phases}
        # the station: 2.5 m radial at bearing 90 deg (north, world y), 5 m up; NED at the double
        wait_until(lambda: np.allclose(peer.snapshot()['position'], [2.5, 0.0, -5.0], atol=0.05),
                   what='the station')
        # ENU in /uav/pose: the bridge streams at 20 Hz, so the latest pose may still be one from the approach
        wait_until(lambda: np.allclose(_position(probe.got['pose'][-1]), (0.0, 2.5, 5.0), atol=0.1),
                   what='the station in /uav/pose (ENU: x east 0, y north 2.5, z up 5)')
        assert (phases[-1].station.x, phases[-1].station.y, phases[-1].station.z) == pytest.approx((0.0, 2.5, 5.0))
        trip = ReelState()
        trip.mode = ReelState.MODE_FAULT
        reel.publish(trip)
        wait_until(lambda: phases[-1].phase == 'return', what='the abort')
        assert phases[-1].aborted and 'reel' in phases[-1].reason
        wait_until(lambda: phases[-1].phase == 'landed', timeout=90, what='landed')
        assert [p.phase for p in phases][-3:] == ['return', 'land', 'landed']
        # over the pad (ENU x 0, y 0.5: NED north 0.5, east 0), never beside the boat where the trip found it
        assert not peer.snapshot()['armed'] and peer.snapshot()['position'][2] > -0.1
        assert np.allclose(peer.snapshot()['position'][:2], [0.5, 0.0], atol=0.5)
    finally:
        probe.close()
        stopped = stop_nodes(processes)
        peer.close()
    assert_clean_exits(stopped)


def test_a_service_server_killed_mid_call_times_the_mission_out_and_it_ends_cleanly(ros_domain, tmp_path):  # noqa: F811
    called = tmp_path / 'called'
    double = subprocess.Popen(
        [sys.executable, str(Path(__file__).parent / 'nodes' / 'uav_services_double.py'), '--ros-args', '-p',
         f'called_file:={called}'], env=dict(os.environ, ROS_DOMAIN_ID=str(ros_domain)), stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True)
    mission = _start('uav_bridge.mission.node', 'uav_link:=services', 'service_timeout:=2.0', 'retry_period:=0.5',
                     domain=ros_domain)
    probe = Probe()
    publish_clock(probe)
    phases = []
    probe.node.create_subscription(MissionState, '/mission/state', phases.append, LATCHED)
    try:
        wait_until(called.exists, timeout=90, what='the mission\'s set_mode call at the server')
        double.kill()                            # the server dies with the call out: no answer will ever come
        double.communicate(timeout=20)
        assert phases[-1].phase == 'guided'
        wait_until(lambda: phases and phases[-1].phase == 'lost', timeout=60, what='the time-out')
    finally:
        probe.close()
        if double.poll() is None:
            double.kill()
            double.communicate(timeout=20)
        stopped = stop_nodes([mission])
    assert phases[-1].aborted
    assert phases[-1].reason.startswith('aborted: autopilot lost: no answer from /uav/set_mode within 2 s (')
    assert_clean_exits(stopped)
    assert 'set_mode: no answer from /uav/set_mode within 2 s' in stopped[0][1]     # the one-line log
