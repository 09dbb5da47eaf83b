"""MAVLink telemetry in ROS conventions: ENU ``world``, FLU ``uav`` body, SI units (no rclpy).

Each function takes pymavlink messages (ArduPilot's, as ``../shared/notes`` describes them)
and returns a sample in the graph's frames (:mod:`uav_bridge.frames`):

* ATTITUDE (roll, pitch, yaw of R_NED←FRD; FRD body rates) → ENU/FLU quaternion, FLU rates;
* LOCAL_POSITION_NED (m, m/s, NED from the EKF origin) + attitude → :class:`Kinematics` in
  ``world``, the EKF origin sitting at ``origin`` (ENU, m) in ``world``;
* HIGHRES_IMU (FRD, m/s², rad/s) + attitude → :class:`ImuSample` (FLU specific force: +9.81
  on z at rest, level);
* GLOBAL_POSITION_INT (degE7, mm above mean sea level) → :class:`GlobalFix`.

Setpoints go the other way: :func:`position_target` turns a ``world`` position (and heading)
into the fields of SET_POSITION_TARGET_LOCAL_NED.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tether_common.rotation import quaternion_rotation
from uav_bridge.frames import enu_to_ned
from uav_bridge.frames import euler_ned_to_quaternion_enu
from uav_bridge.frames import frd_to_flu
from uav_bridge.frames import ned_to_enu

MAV_FRAME_LOCAL_NED = 1
TYPE_MASK_POSITION = 0x0DF8
"""SET_POSITION_TARGET type_mask: position only (velocity, acceleration, yaw, yaw rate ignored)."""
TYPE_MASK_POSITION_YAW = 0x09F8
"""SET_POSITION_TARGET type_mask: position and yaw (velocity, acceleration, yaw rate ignored)."""


@dataclass(frozen=True)
class Attitude:
    """Body attitude and rates from ATTITUDE."""

    boot_time: float           # s, autopilot time since boot
    orientation: np.ndarray    # quaternion (x, y, z, w) of the FLU body in ENU
    rates_body: np.ndarray     # rad/s, FLU


@dataclass(frozen=True)
class Kinematics:
    """Pose and velocity of the UAV in ``world`` (ENU), from LOCAL_POSITION_NED and ATTITUDE."""

    boot_time: float           # s, autopilot time since boot of the position
    position: np.ndarray       # m, ENU in world
    velocity: np.ndarray       # m/s, ENU
    orientation: np.ndarray    # quaternion (x, y, z, w) of the FLU body in ENU
    angular_velocity: np.ndarray   # rad/s, expressed in ENU (world)


@dataclass(frozen=True)
class ImuSample:
    """Inertial measurement of the autopilot's first IMU, body FLU."""

    boot_time: float           # s
    orientation: np.ndarray    # quaternion (x, y, z, w) of the FLU body in ENU (the EKF's)
    angular_velocity: np.ndarray   # rad/s, FLU
    linear_acceleration: np.ndarray   # m/s², FLU specific force


@dataclass(frozen=True)
class GlobalFix:
    """Global position of the UAV."""

    boot_time: float           # s
    latitude: float            # deg
    longitude: float           # deg
    altitude: float            # m above mean sea level
    valid: bool                # False while the autopilot reports no position (lat = lon = 0)


def attitude(msg) -> Attitude:
    """Convert ATTITUDE."""
    return Attitude(msg.time_boot_ms * 1e-3,
                    euler_ned_to_quaternion_enu(msg.roll, msg.pitch, msg.yaw),
                    frd_to_flu([msg.rollspeed, msg.pitchspeed, msg.yawspeed]))


def kinematics(msg, current: Attitude, origin) -> Kinematics:
    """Convert LOCAL_POSITION_NED with the latest attitude; ``origin``: EKF origin in world (ENU, m)."""
    omega_world = quaternion_rotation(current.orientation, 'ATTITUDE').apply(current.rates_body)
    return Kinematics(msg.time_boot_ms * 1e-3,
                      np.asarray(origin, dtype=float) + ned_to_enu([msg.x, msg.y, msg.z]),
                      ned_to_enu([msg.vx, msg.vy, msg.vz]),
                      current.orientation, omega_world)


def imu(msg, current: Attitude) -> ImuSample:
    """Convert HIGHRES_IMU (time_usec since boot) with the latest attitude."""
    return ImuSample(msg.time_usec * 1e-6, current.orientation,
                     frd_to_flu([msg.xgyro, msg.ygyro, msg.zgyro]),
                     frd_to_flu([msg.xacc, msg.yacc, msg.zacc]))


def global_fix(msg) -> GlobalFix:
    """Convert GLOBAL_POSITION_INT."""
    return GlobalFix(msg.time_boot_ms * 1e-3, msg.lat * 1e-7, msg.lon * 1e-7, msg.alt * 1e-3,
                     not (msg.lat == 0 and msg.lon == 0))


@dataclass(frozen=True)
class PositionTarget:
    """The fields of SET_POSITION_TARGET_LOCAL_NED for a position (and heading) target."""

    x: float                   # m, north of the EKF origin
    y: float                   # m, east
    z: float                   # m, down
    yaw: float                 # rad, NED heading (0 north, clockwise), ignored unless in type_mask
    type_mask: int
    coordinate_frame: int = MAV_FRAME_LOCAL_NED


def position_target(position_world, origin, yaw_ned: float | None = None) -> PositionTarget:
    """Return the local NED target of a ``world`` ENU position (m); heading kept unless ``yaw_ned``."""
    x, y, z = enu_to_ned(np.asarray(position_world, dtype=float) - np.asarray(origin, dtype=float))
    if yaw_ned is None:
        return PositionTarget(float(x), float(y), float(z), 0.0, TYPE_MASK_POSITION)
    return PositionTarget(float(x), float(y), float(z), float(yaw_ned), TYPE_MASK_POSITION_YAW)
