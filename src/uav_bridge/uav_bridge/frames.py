"""Frame conventions at the MAVLink boundary: NED/FRD (MAVLink) against ENU/FLU (REP-103).

MAVLink's local frame is NED (x north, y east, z down) and its body frame FRD (x forward,
y right, z down); the graph uses ENU (x east, y north, z up) for ``world`` and FLU (x forward,
y left, z up) for ``uav``. Both changes are proper rotations:

* NED → ENU: 180° about x then 90° about z, i.e. ``(x, y, z)_ENU = (y, x, -z)_NED``;
* FRD → FLU: 180° about x, i.e. ``(x, y, z)_FLU = (x, -y, -z)_FRD``.

An attitude (rotation of the body in the world) therefore converts as
``R_ENU←FLU = R_ENU←NED · R_NED←FRD · R_FRD←FLU``. Quaternions are ``(x, y, z, w)`` as in
geometry_msgs. Each map here is its own inverse (a 180° rotation or a reflection-free swap
applied twice gives the identity), which the tests check as round trips.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

ENU_FROM_NED = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
"""Rotation matrix taking NED coordinates of a vector to ENU coordinates (and back)."""

FLU_FROM_FRD = np.diag([1.0, -1.0, -1.0])
"""Rotation matrix taking FRD coordinates of a vector to FLU coordinates (and back)."""


def ned_to_enu(vector) -> np.ndarray:
    """Return the ENU coordinates of a vector given in NED (positions, velocities)."""
    return ENU_FROM_NED @ np.asarray(vector, dtype=float)


def enu_to_ned(vector) -> np.ndarray:
    """Return the NED coordinates of a vector given in ENU."""
    return ENU_FROM_NED @ np.asarray(vector, dtype=float)


def frd_to_flu(vector) -> np.ndarray:
    """Return the FLU coordinates of a body vector given in FRD (rates, specific force)."""
    return FLU_FROM_FRD @ np.asarray(vector, dtype=float)


def flu_to_frd(vector) -> np.ndarray:
    """Return the FRD coordinates of a body vector given in FLU."""
    return FLU_FROM_FRD @ np.asarray(vector, dtype=float)


def attitude_ned_to_enu(matrix_ned_frd) -> np.ndarray:
    """Return R_ENU←FLU for the body attitude R_NED←FRD."""
    return ENU_FROM_NED @ np.asarray(matrix_ned_frd, dtype=float) @ FLU_FROM_FRD


def attitude_enu_to_ned(matrix_enu_flu) -> np.ndarray:
    """Return R_NED←FRD for the body attitude R_ENU←FLU."""
    return ENU_FROM_NED @ np.asarray(matrix_enu_flu, dtype=float) @ FLU_FROM_FRD


def quaternion_enu_to_ned(quaternion_xyzw) -> tuple[float, float, float, float]:
    """Return R_NED←FRD as a quaternion (w, x, y, z) for the ENU/FLU attitude (x, y, z, w).

    ENU_FROM_NED is the half turn about (1, 1, 0)/√2 and FLU_FROM_FRD the half turn about x,
    so q_NED←FRD = q_(1,1,0) ⊗ q_ENU←FLU ⊗ q_x (scalar-last input, scalar-first output as
    ArduPilot's quaternions), w >= 0.
    """
    x, y, z, w = (float(c) for c in quaternion_xyzw)
    h = math.sqrt(0.5)
    # q ⊗ (1, 0, 0, 0) [x-axis half turn, (x, y, z, w)] = (w, z, -y, -x)
    x, y, z, w = w, z, -y, -x
    # (h, h, 0, 0) ⊗ q, with the sign that makes w >= 0
    sign = -1.0 if x + y > 0.0 else 1.0
    return (sign * h * (-x - y), sign * h * (w + z), sign * h * (w - z), sign * h * (y - x))


def quaternion_to_euler(w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """Return (roll, pitch, yaw) (rad, intrinsic Z-Y-X) of the rotation quaternion (w, x, y, z)."""
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def euler_ned_to_quaternion_enu(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Return the ENU/FLU quaternion (x, y, z, w) of MAVLink ATTITUDE angles.

    ``roll``, ``pitch``, ``yaw`` (rad) are the intrinsic Z-Y-X angles of R_NED←FRD, as
    ATTITUDE carries them (yaw 0 = nose north, positive clockwise seen from above).
    """
    matrix = Rotation.from_euler('ZYX', [yaw, pitch, roll]).as_matrix()
    return Rotation.from_matrix(attitude_ned_to_enu(matrix)).as_quat()


def quaternion_enu_to_yaw_ned(quaternion_xyzw) -> float:
    """Return the NED heading (rad, 0 = north, clockwise positive) of an ENU/FLU quaternion.

    This is the yaw a SET_POSITION_TARGET_LOCAL_NED carries for the body attitude the
    quaternion describes: the heading of the body's x axis (forward) projected on the
    horizontal plane.
    """
    forward_enu = Rotation.from_quat(quaternion_xyzw).apply([1.0, 0.0, 0.0])
    return wrap_angle(math.atan2(forward_enu[0], forward_enu[1]))


def wrap_angle(angle: float) -> float:
    """Return ``angle`` (rad) wrapped into (-π, π]."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped
