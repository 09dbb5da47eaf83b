"""Covariance fields of ROS messages."""

from __future__ import annotations


def diagonal_3x3(variance: float) -> list[float]:
    """Row-major 3 x 3 covariance with ``variance`` on the diagonal (sensor_msgs/Imu's ``*_covariance``)."""
    return [variance, 0.0, 0.0, 0.0, variance, 0.0, 0.0, 0.0, variance]
