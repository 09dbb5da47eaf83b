"""End conditions of the tether: pinned, point mass, rigid body (Eq. 7.13), prescribed motion."""

from __future__ import annotations

from dataclasses import dataclass, field
from collections.abc import Callable

import numpy as np

from tether_dynamics.fem.errors import FemError

Vector = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Pinned:
    """A fixed pivot: the c0 condition removed by model reduction (Sec. 8.3.3).

    Attributes:
        position: (3,) array, m, world frame.
    """

    position: tuple[float, float, float]


@dataclass(frozen=True)
class PrescribedMotion:
    """An end node moved along a given path, e.g. the boat's tether exit point.

    The callables take an array of times (s) of shape (n,) and return (n, 3) arrays of
    position (m), velocity (m/s) and acceleration (m/s^2). They are sampled once on a
    uniform grid (``sample_dt``) before a run; between samples the position and velocity
    are cubic-Hermite interpolated and the acceleration linearly. Samples recorded from a
    topic can be passed the same way with :meth:`from_samples`.
    """

    position: Vector
    velocity: Vector
    acceleration: Vector

    @staticmethod
    def from_samples(times: np.ndarray, position: np.ndarray, velocity: np.ndarray,
                     acceleration: np.ndarray) -> PrescribedMotion:
        """Build a motion from sampled (t, p, v, a), interpolated linearly between samples."""
        times = np.asarray(times, float)

        def interp(table: np.ndarray) -> Vector:
            table = np.asarray(table, float)
            return lambda t: np.stack([np.interp(t, times, table[:, k]) for k in range(3)], axis=-1)
        return PrescribedMotion(interp(position), interp(velocity), interp(acceleration))

    def tables(self, t0: float, t1: float, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Sample position, velocity, acceleration on t0, t0 + dt, ... covering [t0, t1]."""
        n = int(np.ceil((t1 - t0) / dt)) + 3
        t = t0 + dt * np.arange(n)
        tables = [np.asarray(f(t), float).reshape(n, 3) for f in
                  (self.position, self.velocity, self.acceleration)]
        return tables[0], tables[1], tables[2]


@dataclass(frozen=True)
class PointMass:
    """A point mass at the far end (Eq. 7.13 with rho_c = 0).

    Attributes:
        mass: kg
        force: (3,) constant external force on it, N (e.g. thrust), world frame.
    """

    mass: float
    force: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not self.mass > 0.0:
            msg = f'point mass must be positive, got {self.mass}'
            raise FemError(msg)


@dataclass(frozen=True)
class RigidBody:
    """A rigid body hung at its attachment point with offset centre of mass (Eq. 7.6, 7.13).

    Attributes:
        mass: kg
        rho_c: (3,) attachment point to centre of mass, body frame, m.
        inertia: (3, 3) inertia tensor Pi about the attachment point, body frame, kg m^2
            (Eq. 7.6 needs it about the attachment point: T_rb = ... + 1/2 Omega . Pi Omega).
        rotation: (3, 3) initial body-to-world rotation R (columns e_b1, e_b2, e_b3).
        omega: (3,) initial body angular velocity, rad/s.
        force: (3,) constant external force at the attachment point, N, world frame.
    """

    mass: float
    rho_c: tuple[float, float, float]
    inertia: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    omega: tuple[float, float, float] = (0.0, 0.0, 0.0)
    force: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        inertia = np.asarray(self.inertia, float)
        rotation = np.asarray(self.rotation, float)
        if not self.mass > 0.0:
            msg = f'rigid body mass must be positive, got {self.mass}'
            raise FemError(msg)
        if inertia.shape != (3, 3) or not np.allclose(inertia, inertia.T):
            msg = 'rigid body inertia must be a symmetric 3x3 matrix'
            raise FemError(msg)
        if np.any(np.linalg.eigvalsh(inertia) <= 0.0):
            msg = 'rigid body inertia must be positive definite'
            raise FemError(msg)
        if not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9) or np.linalg.det(rotation) < 0:
            msg = 'rigid body rotation must be a proper orthonormal matrix'
            raise FemError(msg)
        rc = np.asarray(self.rho_c, float)
        shift = self.mass * (rc @ rc * np.eye(3) - np.outer(rc, rc))
        if np.any(np.linalg.eigvalsh(inertia - shift) <= 0.0):
            msg = ('rigid body inertia about the attachment point must exceed the '
                   'parallel-axis part m(|rho_c|^2 I - rho_c rho_c^T)')
            raise FemError(msg)


StartEnd = Pinned | PrescribedMotion
FarEnd = Pinned | PrescribedMotion | PointMass | RigidBody
