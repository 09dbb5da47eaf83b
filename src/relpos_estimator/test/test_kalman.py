"""The filter of Eq. 4.6-4.9 on filterpy against an independent numpy implementation of the same equations."""

from __future__ import annotations

import numpy as np

from relpos_estimator.kalman import Covariances
from relpos_estimator.kalman import RelativeAltitudeFilter


def _numpy_filter(dt, cov, p0, steps):
    """Textbook predict/update written from Eq. 4.6-4.9 (no filterpy)."""
    F = np.array([[1, dt, 0, 0, 0], [0, 1, dt, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1.0]])
    Q = np.diag([cov.sigma_z, cov.sigma_zdot, cov.sigma_zddot, cov.sigma_mu1, cov.sigma_mu2])
    H = np.array([[1, 0, 0, 0, 0], [0, 0, 1, 1, 0], [0, 0, 1, 0, 1.0]])
    R = np.diag([cov.sigma_dgps, cov.sigma_acc1, cov.sigma_acc2])
    x, P = np.zeros(5), np.diag(p0)
    out = []
    for i, (y1, y2, gps) in enumerate(steps):
        if i:
            x, P = F @ x, F @ P @ F.T + Q
        rows = [1, 2] + ([0] if gps is not None else [])
        z = np.array([y1, y2] + ([gps] if gps is not None else []))
        Hs, Rs = H[rows], R[np.ix_(rows, rows)]
        S = Hs @ P @ Hs.T + Rs
        K = P @ Hs.T @ np.linalg.inv(S)
        x = x + K @ (z - Hs @ x)
        P = (np.eye(5) - K @ Hs) @ P
        out.append((x.copy(), P.copy()))
    return out


def test_filter_matches_an_independent_numpy_implementation():
    rng = np.random.default_rng(4)
    dt, cov = 0.01, Covariances()
    t = np.arange(0.0, 20.0, dt)
    dz = 5.0 - 0.8 * np.sin(2 * np.pi * t / 8.0)
    accel = 0.8 * (2 * np.pi / 8.0) ** 2 * np.sin(2 * np.pi * t / 8.0)
    steps = []
    for i in range(t.size):
        gps = dz[i] + rng.normal(0, 0.01) if i % 25 == 0 else None
        steps.append((accel[i] + 0.05 + rng.normal(0, 0.02), accel[i] - 0.03 + rng.normal(0, 0.05), gps))
    p0 = [cov.sigma_dgps, 1.0, 1.0, 1.0, 1.0]
    reference = _numpy_filter(dt, cov, p0, steps)
    kf = RelativeAltitudeFilter(cov, dt, p0)
    for i, (y1, y2, gps) in enumerate(steps):
        if i:
            kf.predict()
        kf.update_imu(y1, y2)
        if gps is not None:
            kf.update_dgps(gps)
        np.testing.assert_allclose(kf.x, reference[i][0], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(kf.P, reference[i][1], rtol=1e-7, atol=1e-10)
    # the estimate tracks the truth between fixes (a filter that ignored the IMUs would lag by cm)
    est = np.array([r[0][0] for r in reference])
    assert np.sqrt(np.mean((est[500:] - dz[500:]) ** 2)) < 0.02


def test_a_missing_channel_is_left_out_not_zeroed():
    cov = Covariances()
    a = RelativeAltitudeFilter(cov, 0.01, [1.0] * 5)
    b = RelativeAltitudeFilter(cov, 0.01, [1.0] * 5)
    a.update_imu(None, 0.5)
    b.update_imu(0.0, 0.5)
    assert a.x[2] != b.x[2]
    assert a.P[3, 3] == 1.0  # mu_1 untouched without channel 1
