"""Kinematic ends: the guide way riding on the platform and a prescribed UAV attachment point,
sampled at each call and followed between calls by cubic Hermite interpolation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tether_common.rotation import UnitQuaternion


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b of two 3-vectors (``np.cross`` costs ten times more on one pair)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def point_on_body(position: np.ndarray, rotation: UnitQuaternion, velocity: np.ndarray, omega_world: np.ndarray,
                  offset: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World position and velocity of a point fixed at ``offset`` (body frame) on a moving body."""
    arm = rotation.apply(offset)
    return np.asarray(position, float) + arm, np.asarray(velocity, float) + cross(omega_world, arm)


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
