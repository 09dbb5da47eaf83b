"""Covariances of the relative-altitude filter measured from a recording's sensors against its truth.

The thesis tunes Q and R with Algorithm 1 on trials where the UAV surrogate hangs still
(Sec. 5.2, 6.2); its values weigh the accelerometers so little (R of 91-113 (m/s^2)^2) that a
flying UAV's estimate is a dGPS extrapolation between fixes, 0.1-0.3 m off after a dropout.
Here each entry is the variance (robust: :func:`_robust_var`) of what it models, measured on the recording's ticks k with
the recorded truth (z, v, a: relative altitude, its rate and acceleration):

* ``sigma_acc1``: channel 1, y1 = -a_reel, against a: the UAV's own acceleration, which the
  hover assumption of Sec. 4.4 leaves out, plus the reel IMU's noise;
* ``sigma_acc2``: channel 2, y2 = a_uav - a_reel, against a, its mean (the bias) removed;
* ``sigma_zddot``: the change of a from one tick to the next (the acceleration's random walk);
* ``sigma_z``, ``sigma_zdot``: the random walks in the residuals of Eq. 4.6 on the truth,
  z(k+n) - z(k) - dt sum v and v(k+n) - v(k) - dt sum a over n ticks: the growth of their
  variance from one dGPS period to :data:`WALK_SPAN` s, per tick. From one tick to the next
  the residuals are dominated by the sampling of an acceleration that varies within a tick,
  a bounded error that does not accumulate and that Q, a random walk, must not model;
* ``sigma_mu1``, ``sigma_mu2``: the per-tick random walk that explains how each channel's
  error mean wanders between blocks of :data:`BIAS_BLOCK` s (floored at :data:`FLOOR`);
* ``sigma_dgps``: the mean of the squared vertical sigmas the receiver reports with its
  RTK-fixed fixes.
"""

from __future__ import annotations

import numpy as np

from relpos_estimator.kalman import Covariances
from relpos_estimator.recorded import Recording
from tether_models.dgps import STATUS_RTK_FIXED

BIAS_BLOCK = 10.0
"""s, block length over which a channel's bias is taken as its mean error."""
WALK_SPAN = 4.0
"""s, the longest span over which the model residuals' growth is measured (16 dGPS periods)."""
FLOOR = 1e-9
"""Smallest variance written (SI units squared): no entry of Q or R is zero."""


def _regular(rec: Recording, dt: float) -> list[int]:
    """The longest run of stamps ``dt`` apart that have both IMU samples and the truth."""
    step = int(round(dt * 1e9))
    stamps = [k for k in sorted(rec.reel) if k in rec.uav and k in rec.truth_motion
              and np.isfinite(rec.reel[k]) and np.isfinite(rec.uav[k])]
    runs: list[list[int]] = []
    for k in stamps:
        if runs and k - runs[-1][-1] == step:
            runs[-1].append(k)
        else:
            runs.append([k])
    return max(runs, key=len, default=[])


def _robust_var(x: np.ndarray) -> float:
    """Variance from the median absolute deviation (1.4826 MAD)^2: the take-off and the touchdown, a few
    ticks of ground contact, do not stand for the flight.
    """
    return float((1.4826 * np.median(np.abs(x - np.median(x)))) ** 2)


def _walk(residual, n1: int, n2: int) -> float:
    """Per-tick growth of the variance of ``residual(n)`` (the residual over n ticks) from n1 to n2 ticks."""
    return (_robust_var(residual(n2)) - _robust_var(residual(n1))) / (n2 - n1)


def _channels(rec: Recording, dt: float, period: float) -> tuple[dict[str, np.ndarray], dict[str, float]]:
    """The channels' errors and the acceleration's changes (arrays), and the model residuals' random walks."""
    stamps = _regular(rec, dt)
    z = np.array([rec.truth[k] for k in stamps])
    v, a = np.array([rec.truth_motion[k] for k in stamps]).T
    integral_v = np.concatenate([[0.0], np.cumsum(v)]) * dt
    integral_a = np.concatenate([[0.0], np.cumsum(a)]) * dt

    def z_residual(n: int) -> np.ndarray:
        i = np.arange(0, z.size - n, n)
        return z[i + n] - z[i] - (integral_v[i + n] - integral_v[i])

    def v_residual(n: int) -> np.ndarray:
        i = np.arange(0, v.size - n, n)
        return v[i + n] - v[i] - (integral_a[i + n] - integral_a[i])

    n1, n2 = max(1, int(round(period / dt))), int(round(WALK_SPAN / dt))
    return ({'y1': -np.array([rec.reel[k] for k in stamps]) - a,
             'y2': np.array([rec.uav[k] - rec.reel[k] for k in stamps]) - a, 'da': np.diff(a)},
            {'z_walk': _walk(z_residual, n1, n2), 'v_walk': _walk(v_residual, n1, n2)})


def _bias_walk(error: np.ndarray, dt: float) -> float:
    """Per-tick variance of a random walk whose block means wander as ``error``'s do."""
    n = int(round(BIAS_BLOCK / dt))
    blocks = error[: error.size // n * n].reshape(-1, n).mean(axis=1)
    return _robust_var(np.diff(blocks)) / n if blocks.size > 2 else FLOOR


def measured_covariances(recs: list[Recording], dt: float = 0.01, fix_period: float = 0.25) -> Covariances:
    """Q and R diagonal entries measured on ``recs`` (see the module docstring), SI units squared."""
    channels = [_channels(rec, dt, fix_period) for rec in recs]
    parts = [errors for errors, _ in channels]
    walks = [walk for _, walk in channels]
    joined = {name: np.concatenate([p[name] for p in parts]) for name in ('y1', 'y2', 'da')}
    sigmas = [f.std[2] ** 2 for rec in recs for f in rec.fixes
              if f.status >= STATUS_RTK_FIXED and np.isfinite(f.std[2])]
    values = {
        'sigma_z': np.mean([w['z_walk'] for w in walks]), 'sigma_zdot': np.mean([w['v_walk'] for w in walks]),
        'sigma_zddot': _robust_var(joined['da']),
        'sigma_mu1': np.mean([_bias_walk(p['y1'], dt) for p in parts]),
        'sigma_mu2': np.mean([_bias_walk(p['y2'], dt) for p in parts]),
        'sigma_acc1': _robust_var(joined['y1']), 'sigma_acc2': _robust_var(joined['y2']),
        'sigma_dgps': np.mean(sigmas) if sigmas else Covariances().sigma_dgps,
    }
    return Covariances(**{name: max(FLOOR, float(value)) for name, value in values.items()})
