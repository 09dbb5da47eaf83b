"""The tether's stiffness at the drum against the elastic string's closed form."""

from __future__ import annotations

import math

import pytest

from smart_reel.tension_model import TetherStiffness


def test_taut_tether_is_the_elastic_spring_ea_chord_over_length_squared():
    model = TetherStiffness(0.042, 2.0e4)
    chord = math.hypot(3.22, 6.0)
    length = chord / 1.01  # stretched 1 %: T = EA (chord - L) / L = 200 N, gravity a 1e-3 correction
    assert model.tension(3.22, 6.0, length) == pytest.approx(2.0e4 * (chord - length) / length, rel=0.01)
    assert model(3.22, 6.0, length) == pytest.approx(2.0e4 * chord / length**2, rel=0.01)


def test_hanging_tether_is_soft():
    model = TetherStiffness(0.042, 2.0e4)
    chord = math.hypot(3.22, 6.0)
    assert abs(model(3.22, 6.0, chord + 0.5)) < 1.0  # N/m, against 2900 N/m taut
