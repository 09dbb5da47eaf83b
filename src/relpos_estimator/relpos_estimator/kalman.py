"""The 5-state relative-altitude Kalman filter of thesis Sec. 4.4 (Eq. 4.6-4.9), on filterpy.

State X = [dz, dz_rate, dz_accel, mu_1, mu_2]: the UAV's altitude above the guide way, its
rate and acceleration, and the biases of the two accelerometer channels. The process is
the constant-acceleration model with random-walk biases (Eq. 4.6, 4.7), stepped at the
filter rate (100 Hz). Measurements (Eq. 4.8, 4.9): the dGPS relative altitude
(H = [1 0 0 0 0]) only at the time of a fix - between fixes its variance is infinite, i.e.
no update - and two accelerometer channels (H = [0 0 1 1 0], [0 0 1 0 1]) every step.

Covariance convention: the thesis's tuned "covariance values" sigma (Sec. 6.2) are used as
the diagonal entries of Q (sigma_z, sigma_zdot, sigma_zddot, sigma_mu1, sigma_mu2) and R
(sigma_Acc1, sigma_Acc2, sigma_dGPS), i.e. as variances in SI units squared, which is how
Algorithm 1 tunes them.

Accelerometer channels: the relative acceleration is dz_accel = a_uav - a_reel (world
vertical, gravity removed). Channel 1 is the reel IMU alone, y1 = -a_reel, exact under the
thesis's hover assumption for the UAV (Sec. 4.4) - the UAV's own acceleration enters as
process noise; channel 2 is y2 = a_uav - a_reel from both IMUs. So mu_1 is minus the reel
IMU's vertical bias and mu_2 the UAV IMU's minus the reel IMU's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import fields

import numpy as np
from filterpy.kalman import KalmanFilter

H_DGPS = np.array([[1.0, 0.0, 0.0, 0.0, 0.0]])
"""Eq. 4.8, first row."""
H_IMU = np.array([[0.0, 0.0, 1.0, 1.0, 0.0], [0.0, 0.0, 1.0, 0.0, 1.0]])
"""Eq. 4.8, accelerometer rows."""


@dataclass(frozen=True)
class Covariances:
    """Diagonal entries of Q and R (thesis Sec. 6.2 tuned values as defaults; SI units squared)."""

    sigma_z: float = 0.0133
    sigma_zdot: float = 8.66e-8
    sigma_zddot: float = 0.453
    sigma_mu1: float = 1.473
    sigma_mu2: float = 0.0146
    sigma_acc1: float = 112.94
    sigma_acc2: float = 91.105
    sigma_dgps: float = 0.01

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Field names in Algorithm 1's order."""
        return tuple(f.name for f in fields(cls))

    def values(self) -> np.ndarray:
        """Values in :meth:`names` order."""
        return np.array([getattr(self, n) for n in self.names()])

    @property
    def Q(self) -> np.ndarray:  # noqa: N802 - the book's symbol
        """Process noise covariance (Eq. 4.7)."""
        return np.diag([self.sigma_z, self.sigma_zdot, self.sigma_zddot, self.sigma_mu1, self.sigma_mu2])

    @property
    def R_imu(self) -> np.ndarray:  # noqa: N802
        """Accelerometer measurement covariance (Eq. 4.9)."""
        return np.diag([self.sigma_acc1, self.sigma_acc2])


def transition(dt: float) -> np.ndarray:
    """State transition F of Eq. 4.6 for a step of ``dt`` s."""
    F = np.eye(5)  # noqa: N806
    F[0, 1] = dt
    F[1, 2] = dt
    return F


class RelativeAltitudeFilter:
    """Eq. 4.6-4.9 on :class:`filterpy.kalman.KalmanFilter`; the state can be saved and restored for retrodiction.

    Args:
        covariances: Q and R entries.
        dt: s, filter step (0.01 at 100 Hz).
        initial_variance: diagonal of P at start (SI units squared).
    """

    def __init__(self, covariances: Covariances, dt: float, initial_variance: Sequence[float] | np.ndarray) -> None:
        self.covariances = covariances
        self.kf = KalmanFilter(dim_x=5, dim_z=2)
        self.kf.F = transition(dt)
        self.kf.Q = covariances.Q
        self.kf.H = H_IMU
        self.kf.R = covariances.R_imu
        self.kf.P = np.diag(np.asarray(initial_variance, dtype=float))
        r_imu = covariances.R_imu
        self._imu_rows: dict[tuple[int, ...], tuple[np.ndarray, np.ndarray]] = {
            rows: (H_IMU[list(rows)], r_imu[np.ix_(rows, rows)]) for rows in ((0, 1), (0,), (1,))}
        self._r_dgps = np.array([[covariances.sigma_dgps]])

    @property
    def x(self) -> np.ndarray:
        """State estimate (5,)."""
        return self.kf.x[:, 0]

    @property
    def P(self) -> np.ndarray:  # noqa: N802
        """State covariance (5, 5)."""
        return self.kf.P

    def restore(self, x: np.ndarray, P: np.ndarray) -> None:  # noqa: N803
        """Set the state and covariance (copies)."""
        self.kf.x = np.array(x, dtype=float).reshape(5, 1)
        self.kf.P = np.array(P, dtype=float)

    def predict(self) -> None:
        """One step of Eq. 4.6."""
        self.kf.predict()

    def update_imu(self, y1: float | None, y2: float | None) -> None:
        """Fuse the accelerometer channels that are present (None: missing or rejected sample)."""
        rows = tuple(i for i, y in enumerate((y1, y2)) if y is not None)
        if not rows:
            return
        H, R = self._imu_rows[rows]  # noqa: N806
        self.kf.update(np.array([[y] for y in (y1, y2) if y is not None]), R=R, H=H)

    def update_dgps(self, dz: float, variance: float = 0.0) -> None:
        """Fuse one dGPS relative altitude (Eq. 4.8, first row) with R = max(sigma_dgps, ``variance``).

        ``variance``: the square of the vertical sigma the receiver reports with the fix (m^2). A
        fix the receiver calls worse than the tuned sigma_dgps is weighed as the receiver says
        (a 0.3 m float-grade fix fused at a tuned 0.01 m would pull the altitude and its rate
        as hard as an RTK-fixed one).
        """
        r = self._r_dgps if variance <= self.covariances.sigma_dgps else np.array([[variance]])
        self.kf.update(np.array([[dz]]), R=r, H=H_DGPS)
