"""Synthetic ground truth for the sensor and estimator tests (a test double of the platform and plant)."""

from __future__ import annotations

import numpy as np
import pytest

from tether_models.sensor_suite import Truth


def heave_truth(duration: float, seed: int = 0, rate: float = 100.0, altitude: float = 5.0):
    """(t, Truth) pairs: level reel heaving as three sinusoids (10, 7, 4.5 s; 1 m peak-to-peak each), UAV fixed."""
    rng = np.random.default_rng(seed)
    amplitude = np.array([0.5, 0.3, 0.2])
    omega = 2.0 * np.pi / np.array([10.0, 7.0, 4.5])
    phase = rng.uniform(0.0, 2.0 * np.pi, 3)
    for k in range(int(round(duration * rate)) + 1):
        t = k / rate
        heave = float(np.sum(amplitude * np.sin(omega * t + phase)))
        accel = float(-np.sum(amplitude * omega**2 * np.sin(omega * t + phase)))
        yield t, Truth(np.eye(3), np.zeros(3), np.array([0.0, 0.0, accel]), np.array([2.5, 0.0, altitude - heave]),
                       np.array([0.0, 0.0, -accel]), np.zeros(3))


@pytest.fixture
def truth():
    """The :func:`heave_truth` generator."""
    return heave_truth
