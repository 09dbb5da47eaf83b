"""Spool layers and the encoder's quantised length."""

from __future__ import annotations

import math

import pytest

from smart_reel.spool import Encoder
from smart_reel.spool import SpoolGeometry

SPOOL = SpoolGeometry(0.05, 0.12, 0.0045, 100.0, 0.042)


def test_layers_hold_100_m_of_4p5_mm_tether():
    n = math.floor(0.12 / 0.0045)
    assert SPOOL.turns_per_layer == n == 26
    held = sum(2 * math.pi * r * n for r in SPOOL.layer_radius)
    assert held >= 100.0
    assert held - 2 * math.pi * SPOOL.layer_radius[-1] * n < 100.0
    assert SPOOL.layer_radius[0] == pytest.approx(0.05 + 0.00225)
    steps = [b - a for a, b in zip(SPOOL.layer_radius, SPOOL.layer_radius[1:])]
    assert steps == pytest.approx([0.0045] * len(steps))


def test_radius_shrinks_as_tether_pays_out():
    assert SPOOL.radius(0.1) == SPOOL.layer_radius[-1]
    assert SPOOL.radius(99.99) == SPOOL.layer_radius[0]
    radii = [SPOOL.radius(x) for x in range(1, 100)]
    assert all(a >= b for a, b in zip(radii, radii[1:]))


def test_length_per_spool_angle_is_the_layer_radius():
    start = 20.0
    r = SPOOL.radius(start)
    assert SPOOL.deployed_length(start, 0.0) == pytest.approx(start, abs=1e-12)
    assert SPOOL.deployed_length(start, 0.1) - start == pytest.approx(0.1 * r, rel=1e-9)
    assert SPOOL.deployed_length(start, -0.1) - start == pytest.approx(-0.1 * r, rel=1e-9)
    # ten turns out and back is the identity
    there = SPOOL.deployed_length(start, 20 * math.pi)
    angle_back = SPOOL.winding_angle(100.0 - start) - SPOOL.winding_angle(100.0 - there)
    assert angle_back == pytest.approx(20 * math.pi, rel=1e-12)


def test_wound_inertia_is_the_sum_over_layers():
    n = SPOOL.turns_per_layer
    full = sum(0.042 * 2 * math.pi * r * n * r * r for r in SPOOL.layer_radius[:-1])
    last = 100.0 - sum(2 * math.pi * r * n for r in SPOOL.layer_radius[:-1])
    full += 0.042 * last * SPOOL.layer_radius[-1] ** 2
    assert SPOOL.wound_inertia(0.0) == pytest.approx(full, rel=1e-12)
    assert SPOOL.wound_inertia(100.0) == 0.0


def test_encoder_quantises_the_length_to_one_count():
    encoder = Encoder(8000, 40.0)
    assert encoder.step == pytest.approx(2 * math.pi / 320000)
    start = 20.0
    r = SPOOL.radius(start)
    quantum = r * encoder.step
    for angle in (0.0, 1e-7, 0.37 * encoder.step, encoder.step, 3.5 * encoder.step, 1.234):
        counts = encoder.counts(angle)
        assert counts == math.floor(angle / encoder.step + 1e-9)
        measured = SPOOL.deployed_length(start, encoder.angle(counts))
        true = SPOOL.deployed_length(start, angle)
        assert 0.0 <= true - measured < quantum * (1 + 1e-6)
    assert SPOOL.deployed_length(start, encoder.angle(1)) - start == pytest.approx(quantum, rel=1e-9)
    assert encoder.counts(-0.5 * encoder.step) == -1
