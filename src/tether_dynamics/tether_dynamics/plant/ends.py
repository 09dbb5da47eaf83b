"""Kinematic ends: the guide way riding on the platform and a prescribed UAV attachment point,
sampled at each call and followed between calls by cubic Hermite interpolation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation


def quaternion_rotation(q: np.ndarray, what: str) -> Rotation:
    """The rotation of an (x, y, z, w) quaternion; a one-line error if it is not near unit length."""
    q = np.asarray(q, float)
    norm = float(np.linalg.norm(q)) if q.shape == (4,) else 0.0
    if not np.isfinite(norm) or abs(norm - 1.0) > 1e-3:
        msg = f'{what} must be a unit quaternion (x, y, z, w), got {q.tolist()}'
        raise ValueError(msg)
    return Rotation.from_quat(q / norm)


def point_on_body(position: np.ndarray, rotation: Rotation, velocity: np.ndarray, omega_world: np.ndarray,
                  offset: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World position and velocity of a point fixed at ``offset`` (body frame) on a moving body."""
    arm = rotation.apply(offset)
    return np.asarray(position, float) + arm, np.asarray(velocity, float) + np.cross(omega_world, arm)


@dataclass
class Sample:
    """A kinematic point at time t: position (3,) and velocity (3,)."""

    t: float
    position: np.ndarray
    velocity: np.ndarray


def hermite_table(a: Sample, b: Sample) -> np.ndarray:
    """(4, 3) table [p_a, v_a, p_b, v_b] for :func:`tether_dynamics.plant.kernels.hermite`."""
    return np.ascontiguousarray(np.stack([a.position, a.velocity, b.position, b.velocity]))


def hermite(table: np.ndarray, t_a: float, t_b: float, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity at t on the cubic Hermite segment of ``table`` over [t_a, t_b]."""
    h = t_b - t_a
    if h <= 0.0:
        return table[2].copy(), table[3].copy()
    u = (t - t_a) / h
    h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
    d00, d10, d01, d11 = (6 * u**2 - 6 * u) / h, 3 * u**2 - 4 * u + 1, (-6 * u**2 + 6 * u) / h, 3 * u**2 - 2 * u
    pos = h00 * table[0] + h10 * h * table[1] + h01 * table[2] + h11 * h * table[3]
    vel = d00 * table[0] + d10 * table[1] + d01 * table[2] + d11 * table[3]
    return pos, vel
