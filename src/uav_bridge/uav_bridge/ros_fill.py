"""Fill geometry_msgs vectors and quaternions from arrays (shared by the UAV nodes)."""

from __future__ import annotations


def fill_vector(target, values) -> None:
    """Set x, y, z of a Vector3 or Point from three numbers."""
    target.x, target.y, target.z = (float(v) for v in values)


def fill_quaternion(target, values) -> None:
    """Set x, y, z, w of a Quaternion from (x, y, z, w)."""
    target.x, target.y, target.z, target.w = (float(v) for v in values)
