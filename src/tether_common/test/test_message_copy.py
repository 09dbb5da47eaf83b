"""copy_message: the values a DDS take gives, as Python types, and no object shared with the original."""

from __future__ import annotations

import numpy as np
import pytest
from geometry_msgs.msg import Point
from geometry_msgs.msg import PoseStamped
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from sensor_msgs.msg import Imu
from tether_msgs.msg import DgpsFix
from tether_msgs.msg import TetherNodes
from tether_msgs.msg import TetherState
from visualization_msgs.msg import Marker
from visualization_msgs.msg import MarkerArray

from tether_common import cdr
from tether_common.message_copy import copy_message


def _filled(cls):
    rng = np.random.default_rng(7)
    if cls is PoseStamped:
        msg = PoseStamped()
        msg.header.stamp.sec, msg.header.frame_id = 3, 'world'
        msg.pose.position.x, msg.pose.orientation.w = np.float64(rng.normal()), -0.0
        return msg
    if cls is Imu:
        msg = Imu()
        msg.orientation_covariance = rng.normal(size=9)
        msg.linear_acceleration.z = float('nan')
        return msg
    if cls is TetherNodes:
        msg = TetherNodes()
        msg.positions = [Point(x=float(v)) for v in rng.normal(size=4)]
        msg.tensions = rng.normal(size=4).tolist()
        return msg
    if cls is TetherState:
        msg = TetherState(fidelity='quadratic', element_count=20, fouling=True)
        msg.tension_reel = np.float64(12.5)
        return msg
    if cls is DgpsFix:
        return DgpsFix(status=2, sequence=9)
    marker = Marker(ns='tether', points=[Point(y=1.0), Point(z=2.0)])
    marker.color.r = 0.25
    return MarkerArray(markers=[marker])


@pytest.mark.parametrize('cls', [PoseStamped, Imu, TetherNodes, TetherState, DgpsFix, MarkerArray])
def test_a_copy_is_what_the_cdr_round_trip_gives(cls):
    """Compared as the bytes :func:`tether_common.cdr.serialize` writes, padding 0: rclpy's
    serializer leaves padding uninitialized (a TetherState's byte 17, after the empty frame_id,
    came out 0x10 in one run and 0x00 in the other).
    """
    msg = _filled(cls)
    copied = copy_message(msg)
    received = deserialize_message(serialize_message(msg), cls)
    assert cdr.serialize(copied) == cdr.serialize(received)
    assert repr(copied) == repr(received)  # the same values as the same Python types (float, not numpy.float64)


def test_a_copy_shares_no_mutable_part_with_the_original():
    msg = _filled(TetherNodes)
    copied = copy_message(msg)
    msg.header.stamp.sec = 5
    msg.positions[0].x = 99.0
    msg.tensions[1] = 99.0
    imu = _filled(Imu)
    imu_copy = copy_message(imu)
    imu.orientation_covariance[0] = 99.0
    assert copied.header.stamp.sec == 0 and copied.positions[0].x != 99.0 and copied.tensions[1] != 99.0
    assert imu_copy.orientation_covariance[0] != 99.0
