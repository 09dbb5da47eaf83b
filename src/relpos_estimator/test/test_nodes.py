"""The sensors and estimator nodes on sim time behind the platform node, with the UAV surrogate as truth.

The probe is the time master: it steps ``/clock`` only when every node has acked the last
step, as the bringup does, so what the nodes publish does not depend on how fast they run.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np
import pytest

rclpy = pytest.importorskip('rclpy')

from sensor_msgs.msg import Imu  # noqa: E402
from tether_msgs.msg import DgpsFix  # noqa: E402
from tether_msgs.msg import RelativeEstimate  # noqa: E402
from tether_msgs.msg import RelativePosition  # noqa: E402

from relpos_estimator.sensors_node import STATE_INPUT  # noqa: E402


def test_sensors_and_estimator_track_the_platform(tmp_path, ros_domain, lockstep_master):
    common = ['--ros-args', '-p', 'use_sim_time:=true']
    commands = [
        ['psr_platform_sim.platform_node', '-p', 'profile:=hpr1', '-p', 'profile_duration:=20.0',
         '-p', 'table_steps:=120', '-p', f'cache_dir:={tmp_path}'],
        ['relpos_estimator.sensors_node', '-p', 'truth:=surrogate', '-p', 'seed:=4'],
        ['relpos_estimator.estimator_node'],
    ]
    members = ['/platform', '/sensors', '/estimator']
    env = {**os.environ, **lockstep_master.environment('probe', members)}
    processes = [subprocess.Popen([sys.executable, '-m', c[0], *common, *c[1:]], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, env=env) for c in commands]
    rclpy.init()
    node = rclpy.create_node('probe')
    got = {'imu': [], 'fix': [], 'estimate': [], 'truth': []}
    node.create_subscription(Imu, '/imu/reel', got['imu'].append, STATE_INPUT)
    node.create_subscription(DgpsFix, '/dgps/fix', got['fix'].append, STATE_INPUT)
    node.create_subscription(RelativeEstimate, '/estimate/relative', got['estimate'].append, STATE_INPUT)
    node.create_subscription(RelativePosition, '/truth/relative', got['truth'].append, STATE_INPUT)
    master = lockstep_master(node, members, processes)
    try:
        sim_ns = 0
        master.wait_acked(0)  # every node joined, the probe's publishers matched
        while sim_ns < 8_000_000_000:  # /clock advances only once every node has acked it, as in a run
            sim_ns += 10_000_000
            master.step_to(sim_ns)
        end = time.monotonic() + 2.0
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.01)
    finally:
        logs = master.stop()
        node.destroy_node()
        rclpy.shutdown()
    assert all(p.returncode == 0 for p in processes), logs
    assert len(got['imu']) > 400 and len(got['estimate']) > 400, {k: len(v) for k, v in got.items()}
    fix_times = sorted(f.fix_time.sec + f.fix_time.nanosec * 1e-9 for f in got['fix'])
    assert len(fix_times) >= 20  # 4 Hz over the 8 s (the probe may miss a few best-effort messages)
    assert np.allclose(np.round(np.array(fix_times) / 0.25) * 0.25, fix_times, atol=1e-6)
    for f in got['fix']:  # arrival after the receiver's time of fix (latency)
        assert f.header.stamp.sec + f.header.stamp.nanosec * 1e-9 > f.fix_time.sec + f.fix_time.nanosec * 1e-9
    truth = {(m.header.stamp.sec, m.header.stamp.nanosec): m.position.z for m in got['truth']}
    err = [e.dz - truth[(e.header.stamp.sec, e.header.stamp.nanosec)] for e in got['estimate']
           if e.initialized and (e.header.stamp.sec, e.header.stamp.nanosec) in truth
           and e.header.stamp.sec >= 3]
    assert len(err) > 200
    assert np.sqrt(np.mean(np.square(err))) < 0.03
    stamps = [e.header.stamp.sec * 10**9 + e.header.stamp.nanosec for e in got['estimate']]
    assert all(s % 10_000_000 == 0 for s in stamps)
