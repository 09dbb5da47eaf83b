"""The estimator on a flying UAV: the flight scenes' measured Q and R against the thesis's, and the measurement.

A UAV flying under a tether is not the still surrogate of Sec. 5.2: its attachment
accelerates (a slow altitude oscillation and a fast jitter, as the built-in UAV's under its
tether), so the second accelerometer channel carries information the first does not, and
the outdoor dGPS drops fixes. The thesis's covariances weigh the accelerometers so little
that the estimate is a dGPS extrapolation, 0.1-0.3 m off after a dropout (the default
scene's abort); the measured ones follow the accelerometers between fixes.
"""

from __future__ import annotations

import numpy as np
import pytest

from relpos_estimator.estimator import Estimator
from relpos_estimator.estimator_params import PARAMETERS
from relpos_estimator.estimator_params import configs
from relpos_estimator.kalman import Covariances
from relpos_estimator.noise import measured_covariances
from relpos_estimator.offline import run
from relpos_estimator.recorded import Recording
from tether_bringup.scene import find_scene
from tether_bringup.scene import load_scene
from tether_models.dgps import DgpsConfig
from tether_models.sensor_suite import SensorSuite
from tether_models.sensor_suite import SuiteConfig
from tether_models.sensor_suite import Truth

DURATION = 120.0
RATE = 100.0
TABLE_6_3_BOUND = 0.015
"""m, the flight RMSE the issue asks for (thesis Table 6.3: 8-12 mm)."""


def flight_truth(seed: int):
    """(t, Truth): the reel heaving as three sinusoids (1 m peak-to-peak each), the UAV holding 30 m up with a
    5 cm, 3 s altitude oscillation and a 1.5 m/s^2, 23 Hz acceleration jitter.
    """
    rng = np.random.default_rng(seed)
    amplitude, omega = np.array([0.5, 0.3, 0.2]), 2.0 * np.pi / np.array([10.0, 7.0, 4.5])
    phase = rng.uniform(0.0, 2.0 * np.pi, 5)
    uav_amplitude = np.array([0.05, 1.5 / (2.0 * np.pi * 23.0) ** 2])
    uav_omega = 2.0 * np.pi / np.array([3.0, 1.0 / 23.0])
    for k in range(int(round(DURATION * RATE)) + 1):
        t = k / RATE
        heave = float(np.sum(amplitude * np.sin(omega * t + phase[:3])))
        reel_accel = float(-np.sum(amplitude * omega**2 * np.sin(omega * t + phase[:3])))
        uav = float(np.sum(uav_amplitude * np.sin(uav_omega * t + phase[3:])))
        uav_accel = float(-np.sum(uav_amplitude * uav_omega**2 * np.sin(uav_omega * t + phase[3:])))
        uav_rate = float(np.sum(uav_amplitude * uav_omega * np.cos(uav_omega * t + phase[3:])))
        reel_rate = float(np.sum(amplitude * omega * np.cos(omega * t + phase[:3])))
        yield t, Truth(np.eye(3), np.zeros(3), np.array([0.0, 0.0, reel_accel]),
                       np.array([15.0, 0.0, 30.0 + uav - heave]), np.array([0.0, 0.0, uav_accel - reel_accel]),
                       np.zeros(3), np.array([0.0, 0.0, uav_rate - reel_rate]))


def _scene_estimator() -> Estimator:
    """The estimator as the outdoor_flight scene configures it."""
    scene = load_scene(find_scene('outdoor_flight'))
    given = next(n.parameters for n in scene.nodes if n.executable == 'estimator')
    return Estimator(*configs({**{spec.name: spec.default for spec in PARAMETERS}, **given}))


def _rmse(estimator: Estimator, seed: int) -> float:
    trace = run(flight_truth(seed), SensorSuite(SuiteConfig(), DgpsConfig(miss_rate=0.05), seed), estimator)
    a = trace.arrays()
    settled = a['t'] > 5.0
    return float(np.sqrt(np.mean((a['dz'] - a['truth'])[settled] ** 2)))


@pytest.mark.parametrize('seed', [1, 2])
def test_the_flight_scene_estimates_a_flying_uav_within_table_6_3_through_dropouts(seed):
    """Fails with the thesis's covariances, which the default scene used: 33-47 mm on these flights (the scene's: 8 mm)."""
    scene = _rmse(_scene_estimator(), seed)
    thesis = _rmse(Estimator(Covariances()), seed)
    assert scene <= TABLE_6_3_BOUND, f'{scene * 1e3:.1f} mm'
    assert thesis > 2.0 * scene, f'thesis {thesis * 1e3:.1f} mm against measured {scene * 1e3:.1f} mm'


def test_measured_covariances_recover_the_noise_the_recording_was_made_with():
    """Channel noise and the UAV's own acceleration of a synthetic recording come back as R (within 10 %)."""
    rng = np.random.default_rng(7)
    rec = Recording('synthetic')
    n = 6000
    t = np.arange(n) / RATE
    a = 0.8 * np.sin(2.0 * np.pi * t / 6.0)
    v = -0.8 * 6.0 / (2.0 * np.pi) * np.cos(2.0 * np.pi * t / 6.0)
    z = -0.8 * (6.0 / (2.0 * np.pi)) ** 2 * np.sin(2.0 * np.pi * t / 6.0)
    a_uav = rng.normal(0.0, 0.7, n)
    reel = a_uav - a + rng.normal(0.0, 0.02, n)          # y1 = -a_reel = a - a_uav + noise
    for k in range(n):
        stamp = int(round(t[k] * 1e9))
        rec.reel[stamp] = float(reel[k])
        rec.uav[stamp] = float(reel[k] + a[k] + 0.05 + rng.normal(0.0, 0.1))    # y2 = a + bias + noise
        rec.truth[stamp] = float(z[k])
        rec.truth_motion[stamp] = (float(v[k]), float(a[k]))
    measured = measured_covariances([rec])
    assert measured.sigma_acc2 == pytest.approx(0.1**2, rel=0.1)
    assert measured.sigma_acc1 == pytest.approx(0.7**2 + 0.02**2, rel=0.1)
    assert measured.sigma_z <= 1e-6 and measured.sigma_zdot <= 1e-6     # the truth follows Eq. 4.6 (thesis: 1e-2)
