"""MAVLink messages to ROS-convention samples and setpoints back, with known values."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

os.environ.setdefault('MAVLINK20', '1')

from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

from uav_bridge.frames import quaternion_enu_to_yaw_ned  # noqa: E402
from uav_bridge.mavlink import telemetry  # noqa: E402

ENCODER = mavlink.MAVLink(None, 1, 1)


def test_kinematics_of_a_known_pose():
    att = telemetry.attitude(ENCODER.attitude_encode(1000, 0.0, 0.0, math.pi / 2, 0.0, 0.0, 0.2))
    local = ENCODER.local_position_ned_encode(1020, 10.0, 5.0, -15.0, 1.0, 2.0, -3.0)
    sample = telemetry.kinematics(local, att, origin=(100.0, -50.0, 1.5))
    assert sample.boot_time == pytest.approx(1.02)
    np.testing.assert_allclose(sample.position, [105.0, -40.0, 16.5])
    np.testing.assert_allclose(sample.velocity, [2.0, 1.0, 3.0])
    # heading east: the FLU nose points along ENU x
    np.testing.assert_allclose(Rotation.from_quat(sample.orientation).apply([1.0, 0.0, 0.0]), [1.0, 0.0, 0.0],
                               atol=1e-12)
    # clockwise yaw rate 0.2 rad/s (seen from above) is -0.2 about the ENU z axis
    np.testing.assert_allclose(sample.angular_velocity, [0.0, 0.0, -0.2], atol=1e-12)


def test_imu_at_rest_reads_plus_g_up():
    att = telemetry.attitude(ENCODER.attitude_encode(0, 0.0, 0.0, 0.3, 0.01, -0.02, 0.03))
    sample = telemetry.imu(ENCODER.highres_imu_encode(2_500_000, 0.1, -0.2, -9.81, 0.01, -0.02, 0.03,
                                                      0, 0, 0, 0, 0, 0, 0, 0x1FFF), att)
    assert sample.boot_time == pytest.approx(2.5)
    np.testing.assert_allclose(sample.linear_acceleration, [0.1, 0.2, 9.81], rtol=1e-6)
    np.testing.assert_allclose(sample.angular_velocity, [0.01, 0.02, -0.03], rtol=1e-6)


def test_global_fix_units_and_validity():
    fix = telemetry.global_fix(ENCODER.global_position_int_encode(5000, -353632621, 1491652374, 594090, 10000,
                                                                  0, 0, 0, 0))
    assert (fix.latitude, fix.longitude, fix.altitude, fix.valid) == pytest.approx(
        (-35.3632621, 149.1652374, 594.09, True))
    assert not telemetry.global_fix(ENCODER.global_position_int_encode(5000, 0, 0, 0, 0, 0, 0, 0, 0)).valid


def test_position_target_is_local_ned_from_the_origin():
    target = telemetry.position_target([5.0, 10.0, 15.0], origin=(1.0, 2.0, 0.5))
    assert (target.x, target.y, target.z) == pytest.approx((8.0, 4.0, -14.5))
    assert target.type_mask == telemetry.TYPE_MASK_POSITION == 0x0DF8   # the note's position-only mask
    assert target.coordinate_frame == mavlink.MAV_FRAME_LOCAL_NED
    with_yaw = telemetry.position_target([0.0, 0.0, 1.0], origin=(0.0, 0.0, 0.0), yaw_ned=1.0)
    assert with_yaw.type_mask & 0x0400 == 0 and with_yaw.type_mask & 0x0007 == 0
    assert with_yaw.yaw == 1.0


def test_setpoint_heading_round_trip_through_attitude():
    """A heading taken from a published pose, sent back as a target, is the autopilot's heading."""
    for yaw in np.linspace(-3.0, 3.0, 13):
        att = telemetry.attitude(ENCODER.attitude_encode(0, 0.05, -0.1, yaw, 0.0, 0.0, 0.0))
        assert quaternion_enu_to_yaw_ned(att.orientation) == pytest.approx(yaw, abs=1e-9)
