"""The tethered-flight report on a bag of known forces, poses and phases."""

from __future__ import annotations

import pytest

pytest.importorskip('rclpy')

from geometry_msgs.msg import PoseStamped  # noqa: E402
from geometry_msgs.msg import WrenchStamped  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from tether_msgs.msg import MissionState  # noqa: E402

from tether_bringup.bag_writer import BagWriter  # noqa: E402
from tether_bringup.bag_writer import QosRecord  # noqa: E402
from uav_bridge.json_physics.tether_flight_report import tether_flight_report  # noqa: E402


def _stamped(msg, t):
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(round(t * 1e9), 1_000_000_000)
    return msg


def test_force_and_estimate_error_over_the_hold(tmp_path):
    writer = BagWriter(tmp_path / 'bag')
    for topic, kind in [('/tether/uav_wrench', 'geometry_msgs/msg/WrenchStamped'),
                        ('/uav/pose', 'geometry_msgs/msg/PoseStamped'),
                        ('/autopilot/pose', 'geometry_msgs/msg/PoseStamped'),
                        ('/mission/state', 'tether_msgs/msg/MissionState')]:
        writer.add_topic(topic, kind, [QosRecord()])
    for k in range(1, 1001):                        # 10 s at 100 Hz; at the station from 1 s: window from 6 s
        t = 0.01 * k
        wrench = _stamped(WrenchStamped(), t)
        wrench.wrench.force.x, wrench.wrench.force.z = (-4.0, -3.0) if t >= 1.0 else (-40.0, 10.0)
        writer.write('/tether/uav_wrench', serialize_message(wrench), round(t * 1e9))
        pose = _stamped(PoseStamped(), t)
        pose.pose.position.z = 30.0
        writer.write('/uav/pose', serialize_message(pose), round(t * 1e9))
        if k % 10 == 0:
            estimate = _stamped(PoseStamped(), t)
            estimate.pose.position.z = 30.2
            writer.write('/autopilot/pose', serialize_message(estimate), round(t * 1e9))
    for t, phase in [(0.5, 'climb'), (1.0, 'hold')]:
        state = _stamped(MissionState(), t)
        state.phase, state.station.z = phase, 30.0
        writer.write('/mission/state', serialize_message(state), round(t * 1e9))
    writer.close()
    lines = tether_flight_report(str(tmp_path / 'bag'), str(tmp_path / 'out'))
    assert lines[0] == ('tether on the UAV (hold, 401 samples): 3.00 N down, 4.00 N sideways (mean), '
                        '|F| 5.00 N mean, 0.00 N peak-to-peak')
    assert lines[1].startswith('autopilot estimate (/autopilot/pose) against the true UAV: mean 0.200 m, max 0.200 m')
    assert (tmp_path / 'out' / 'uav_tether_force.png').stat().st_size > 1000
