"""The closed-form slope of the guide-way tension against a central difference of the plant's tension."""

from __future__ import annotations

import math

import numpy as np
import pytest

from smart_reel.tension_model import TetherStiffness
from tether_dynamics.plant import quasi_static

G = 9.81
SHORT = math.hypot(3.22, 6.0)
LONG = math.hypot(15.0, 28.0)
GEOMETRIES = {
    'slack': (15.0, 28.0, 33.3),
    'slack short': (5.0, 3.0, 8.0),
    'slack level': (10.0, 0.0, 12.0),
    'slack below': (10.0, -5.0, 12.0),
    'nearly taut': (3.22, 6.0, SHORT * (1.0 + 1e-4)),
    'nearly taut long': (15.0, 28.0, LONG * (1.0 + 1e-4)),
    'barely stretched': (3.22, 6.0, SHORT * (1.0 - 1e-6)),
    'stretched': (3.22, 6.0, SHORT / 1.01),
    'stretched long': (15.0, 28.0, LONG / 1.001),
    'vertical up': (0.0, 20.0, 25.0),
    'vertical down': (0.0, -20.0, 25.0),
    'vertical up taut': (0.0, 20.0, 19.0),
    'vertical down taut': (0.0, -20.0, 19.0),
    'tiny dr up': (1e-9, 20.0, 25.0),
    'tiny dr down': (1e-9, -20.0, 25.0),
}
TETHERS = {'light': (0.0145, 2.0e4), 'thesis': (0.042, 2.0e4), 'soft': (0.042, 500.0)}


def _tension_a(dr: float, dz: float, length: float, mu: float, ea: float) -> float:
    return quasi_static.end_tensions(np.zeros(3), np.array([dr, 0.0, dz]), length, mu, ea, G)[0]


def _central_difference(dr: float, dz: float, length: float, mu: float, ea: float) -> float:
    """dT_A/dL by central differences over h, h/2, h/4 extrapolated to O(h^6) (Richardson).

    h is a tenth of the distance to the taut transition (L = chord), over which the slope
    changes, and long enough that the plant's root tolerance on L_s (1e-12 L) stays below
    1e-6 of the slope.
    """
    h = 0.1 * min(length, abs(length - math.hypot(dr, dz)))

    def central(step: float) -> float:
        return (_tension_a(dr, dz, length + step, mu, ea) - _tension_a(dr, dz, length - step, mu, ea)) / (2.0 * step)

    def extrapolated(step: float) -> float:
        return (4.0 * central(0.5 * step) - central(step)) / 3.0

    return (16.0 * extrapolated(0.5 * h) - extrapolated(h)) / 15.0


@pytest.mark.parametrize('tether', TETHERS.values(), ids=TETHERS.keys())
@pytest.mark.parametrize('geometry', GEOMETRIES.values(), ids=GEOMETRIES.keys())
def test_slope_is_the_central_difference_of_the_plant_tension(geometry: tuple, tether: tuple) -> None:
    dr, dz, length = geometry
    mu, ea = tether
    slope = quasi_static.tension_a_slope(dr, dz, length, mu, ea, G)
    assert math.isfinite(slope)
    assert slope == pytest.approx(_central_difference(dr, dz, length, mu, ea), rel=1e-5, abs=1e-6)
    assert TetherStiffness(mu, ea, G)(dr, dz, length) == -slope
