"""The platform node on sim time: publishes state, reel pose and IMU stamped with /clock."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

rclpy = pytest.importorskip('rclpy')

from geometry_msgs.msg import PoseStamped  # noqa: E402
from geometry_msgs.msg import TwistStamped  # noqa: E402
from sensor_msgs.msg import Imu  # noqa: E402
from tether_msgs.msg import PlatformState  # noqa: E402

from psr_platform_sim.platform_params import PARAMETERS  # noqa: E402
from psr_platform_sim.platform_params import from_params  # noqa: E402
from psr_platform_sim.simulator import PlatformSimulator  # noqa: E402
from tether_common.qos import SENSOR  # noqa: E402
from tether_common.qos import STATE  # noqa: E402


def _start_node(tmp_path, *extra, env=None):
    env = {**os.environ, **(env or {})}
    cmd = [sys.executable, '-m', 'psr_platform_sim.platform_node', '--ros-args',
           '-p', 'use_sim_time:=true', '-p', f'cache_dir:={tmp_path}', '-p', 'table_steps:=120',
           '-p', 'profile_duration:=20.0', *extra]
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_node_publishes_on_sim_time(tmp_path, ros_domain, lockstep_master):
    process = _start_node(tmp_path, '-p', 'profile:=hpr3', '-p', 'seed:=3',
                          env=lockstep_master.environment('probe', ['/platform']))
    rclpy.init()
    node = rclpy.create_node('probe')
    got = {'state': [], 'pose': [], 'twist': [], 'imu': []}
    node.create_subscription(PlatformState, '/platform/state', got['state'].append, STATE)
    node.create_subscription(PoseStamped, '/platform/reel_pose', got['pose'].append, STATE)
    node.create_subscription(TwistStamped, '/platform/reel_twist', got['twist'].append, STATE)
    node.create_subscription(Imu, '/platform/imu', got['imu'].append, SENSOR)
    master = lockstep_master(node, ['/platform'], [process])
    try:
        master.wait_acked(0)  # joined
        sim_ns = 1_000_000_000  # the clock starts late: the node runs every tick from the first
        for _ in range(60):  # /clock advances once the node has acked the last step, as in a run
            sim_ns += 10_000_000
            master.step_to(sim_ns)
        end = time.monotonic() + 1.0
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.01)
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=20)
        node.destroy_node()
        rclpy.shutdown()
    assert min(len(v) for v in got.values()) >= 50
    state = got['state'][-1]
    stamp = state.header.stamp.sec + state.header.stamp.nanosec * 1e-9
    assert 0.0 < stamp <= sim_ns * 1e-9  # every tick from the first, in order, however late the clock started
    assert state.header.frame_id == 'world'
    assert len(state.slider_height) == 3
    assert got['pose'][-1].header.frame_id == 'world'
    q = got['pose'][-1].pose.orientation
    assert abs(q.x**2 + q.y**2 + q.z**2 + q.w**2 - 1.0) < 1e-9
    accel_z = [m.linear_acceleration.z for m in got['imu']]
    assert 8.0 < sum(accel_z) / len(accel_z) < 11.6
    assert process.returncode == 0
    # stamped with the 10 ms ticks (the probe may miss some); the state is the simulator's at that time
    stamps = [m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec for m in got['state']]
    assert all(t % 10_000_000 == 0 for t in stamps)
    assert all(b > a for a, b in zip(stamps, stamps[1:]))
    values = {spec.name: spec.default for spec in PARAMETERS}
    values.update(profile='hpr3', seed=3, cache_dir=str(tmp_path), table_steps=120, profile_duration=20.0)
    sim = PlatformSimulator(from_params(values))
    expected = sim.sample(stamp)
    assert [state.roll, state.pitch, state.yaw] == pytest.approx([expected.roll, expected.pitch, expected.yaw],
                                                                  abs=1e-12)
    assert state.heave == pytest.approx(expected.heave, abs=1e-12)
    assert state.commanded_pitch == pytest.approx(expected.commanded_pitch, abs=1e-12)
    # every reel pose's orientation has the REP-103 angles the state publishes for its stamp
    for m in got['pose']:
        q = m.pose.orientation
        angles = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_euler('ZYX')[::-1]
        sample = sim.sample(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9)
        np.testing.assert_allclose([sample.roll, sample.pitch, sample.yaw], angles, rtol=0.0, atol=1e-9)
    assert {m.header.frame_id for m in got['imu']} == {'boat'}
    for m in got['twist']:
        sample = sim.sample(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9)
        assert m.header.frame_id == 'world'
        np.testing.assert_allclose([m.twist.linear.x, m.twist.linear.y, m.twist.linear.z], sample.reel_velocity,
                                   rtol=0.0, atol=1e-12)
        np.testing.assert_allclose([m.twist.angular.x, m.twist.angular.y, m.twist.angular.z],
                                   sample.world_angular_velocity, rtol=0.0, atol=1e-12)


def test_node_bad_profile_file_exits_2(tmp_path, ros_domain):
    process = _start_node(tmp_path, '-p', f'profile:={tmp_path / "missing.csv"}')
    _, err = process.communicate(timeout=60)
    assert process.returncode == 2
    assert 'missing.csv' in err
    assert 'Traceback' not in err
