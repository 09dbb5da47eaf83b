"""Message <-> core conversions shared by the nodes and the bag tools (duck-typed: rclpy or rosbags messages)."""

from __future__ import annotations

import math

import numpy as np

from tether_models.dgps import Fix
from tether_models.imu import vertical_acceleration


def stamp_ns(stamp) -> int:
    """Nanoseconds of a builtin_interfaces/Time."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def split_ns(seconds: float) -> tuple[int, int]:
    """(sec, nanosec) of a time in seconds, rounded to the nanosecond."""
    return divmod(int(round(seconds * 1e9)), 1_000_000_000)


def imu_vertical(msg) -> float:
    """World-vertical acceleration (m/s^2, gravity removed) of a sensor_msgs/Imu; NaN if a field is not finite."""
    q, a = msg.orientation, msg.linear_acceleration
    values = (q.x, q.y, q.z, q.w, a.x, a.y, a.z)
    if not all(map(math.isfinite, values)):
        return math.nan
    return vertical_acceleration(np.array(values[:4]), np.array(values[4:]))


def fix_from_message(msg) -> Fix:
    """The core's :class:`Fix` of a tether_msgs/DgpsFix."""
    p, s = msg.relative_position, msg.position_std
    return Fix(stamp_ns(msg.header.stamp) * 1e-9, stamp_ns(msg.fix_time) * 1e-9, np.array([p.x, p.y, p.z]),
               np.array([s.x, s.y, s.z]), msg.status, msg.sequence)
