"""ENU/NED and FLU/FRD conversions: round trips and poses whose answer is known by geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from uav_bridge.frames import attitude_enu_to_ned
from uav_bridge.frames import attitude_ned_to_enu
from uav_bridge.frames import enu_to_ned
from uav_bridge.frames import euler_ned_to_quaternion_enu
from uav_bridge.frames import flu_to_frd
from uav_bridge.frames import frd_to_flu
from uav_bridge.frames import ned_to_enu
from uav_bridge.frames import quaternion_enu_to_yaw_ned
from uav_bridge.frames import wrap_angle

RNG = np.random.default_rng(14)


def _axes(roll, pitch, yaw):
    """Forward, left and up axes of the FLU body in ENU for ATTITUDE angles."""
    matrix = Rotation.from_quat(euler_ned_to_quaternion_enu(roll, pitch, yaw)).as_matrix()
    return matrix[:, 0], matrix[:, 1], matrix[:, 2]


def test_vectors_round_trip():
    for vector in RNG.normal(size=(50, 3)) * 30.0:
        np.testing.assert_allclose(enu_to_ned(ned_to_enu(vector)), vector, atol=1e-12)
        np.testing.assert_allclose(flu_to_frd(frd_to_flu(vector)), vector, atol=1e-12)


def test_attitudes_round_trip_and_stay_rotations():
    for matrix in Rotation.random(50, random_state=14).as_matrix():
        converted = attitude_ned_to_enu(matrix)
        np.testing.assert_allclose(converted @ converted.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(converted) == pytest.approx(1.0)
        np.testing.assert_allclose(attitude_enu_to_ned(converted), matrix, atol=1e-12)


def test_known_positions_and_velocities():
    # 10 m north, 5 m east, 15 m up (z down = -15): ENU x east, y north, z up
    np.testing.assert_allclose(ned_to_enu([10.0, 5.0, -15.0]), [5.0, 10.0, 15.0])
    np.testing.assert_allclose(ned_to_enu([0.0, 0.0, 2.0]), [0.0, 0.0, -2.0])   # descending at 2 m/s
    np.testing.assert_allclose(enu_to_ned([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0])    # east stays east


def test_known_body_vectors():
    # level at rest an accelerometer reads -g on FRD z (pointing down), +g on FLU z (up)
    np.testing.assert_allclose(frd_to_flu([0.0, 0.0, -9.81]), [0.0, 0.0, 9.81])
    # yawing clockwise seen from above: +r in FRD, negative about FLU z (which points up)
    np.testing.assert_allclose(frd_to_flu([0.0, 0.0, 0.1]), [0.0, 0.0, -0.1])
    # rolling right wing down: +p about FRD x, +p about FLU x (same axis)
    np.testing.assert_allclose(frd_to_flu([0.2, 0.0, 0.0]), [0.2, 0.0, 0.0])


@pytest.mark.parametrize('yaw, nose', [(0.0, [0.0, 1.0, 0.0]), (math.pi / 2, [1.0, 0.0, 0.0]),
                                       (math.pi, [0.0, -1.0, 0.0]), (-math.pi / 2, [-1.0, 0.0, 0.0])])
def test_heading_points_the_nose(yaw, nose):
    forward, left, up = _axes(0.0, 0.0, yaw)
    np.testing.assert_allclose(forward, nose, atol=1e-12)
    np.testing.assert_allclose(up, [0.0, 0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(np.cross(up, forward), left, atol=1e-12)   # left = up x forward


def test_pitch_up_raises_the_nose_and_roll_right_lowers_the_right_wing():
    pitch = math.radians(10.0)
    forward, _, _ = _axes(0.0, pitch, 0.0)      # heading north, nose up 10 deg
    np.testing.assert_allclose(forward, [0.0, math.cos(pitch), math.sin(pitch)], atol=1e-12)
    roll = math.radians(20.0)
    _, left, _ = _axes(roll, 0.0, 0.0)          # heading north, right wing down 20 deg
    np.testing.assert_allclose(left, [-math.cos(roll), 0.0, math.sin(roll)], atol=1e-12)


def test_yaw_ned_of_an_enu_quaternion_inverts_the_attitude():
    for roll, pitch, yaw in zip(RNG.uniform(-1.0, 1.0, 30), RNG.uniform(-1.3, 1.3, 30), RNG.uniform(-3.1, 3.1, 30)):
        quaternion = euler_ned_to_quaternion_enu(roll, pitch, yaw)
        assert quaternion_enu_to_yaw_ned(quaternion) == pytest.approx(yaw, abs=1e-9)


def test_wrap_angle():
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert wrap_angle(-math.pi) == pytest.approx(math.pi)
    assert wrap_angle(0.5) == 0.5
