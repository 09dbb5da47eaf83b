"""Tests of the reference-length model for the reel controller, thesis Sec. 4.3."""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.statics import heave_robustness, reference_length


@pytest.mark.parametrize('ratio', [0.1, 0.46, 1.0])
def test_poly3_is_eq_4_4_inside_its_range(ratio: float) -> None:
    dz = 30.0
    result = reference_length.reference_length(ratio * dz, dz)
    c1, c2, c3, c4 = 0.9964, 0.1514, 0.4674, -0.1280
    dr = ratio * dz
    assert result.model == 'poly3'
    assert result.length == pytest.approx(c1 * dz + c2 * dr + c3 * dr**2 / dz + c4 * dr**3 / dz**2)


def test_blend_runs_from_eq_4_4_at_1_1_to_eq_4_5_at_1_3() -> None:
    dz = 20.0
    d1, d2, d3 = 0.9748, 0.2615, 0.2370
    at_13 = reference_length.reference_length(1.3 * dz, dz)
    assert at_13.length == pytest.approx(dz * (d1 + d2 * 1.3 + d3 * 1.3**2))
    assert reference_length.reference_length(1.2 * dz, dz).model == 'blend'
    ratio = np.linspace(1.0, 1.4, 4001)
    lengths, _ = reference_length.reference_lengths(ratio * dz, np.full_like(ratio, dz))
    # Continuous: no jump bigger than the slope times the step.
    assert np.max(np.abs(np.diff(lengths))) < 2.0 * dz * (ratio[1] - ratio[0]) * 2.0


def test_never_returns_nonsense_outside_the_fit() -> None:
    rng = np.random.default_rng(4)
    dr = rng.uniform(0.0, 100.0, 3000)
    dz = rng.uniform(-20.0, 60.0, 3000)
    dz[:100] = rng.uniform(1e-4, 0.1, 100)
    lengths, names = reference_length.reference_lengths(dr, dz)
    assert set(names) <= set(reference_length.MODELS)
    chord = np.hypot(dr, dz)
    assert np.all(lengths >= chord)
    above = dz > 0.0
    slack = heave_robustness.slack_length(dr[above], dz[above])
    assert np.all(lengths[above] <= slack * (1 + 1e-12))
    np.testing.assert_array_equal(lengths[~above], chord[~above])
    assert np.all(names[~above] == 'clamped')
    assert np.all(names[above & (dr > 2.0 * dz)] == 'exact')
    # Eq. 4.4 alone goes to -100 km here; the model uses the exact solve.
    far = reference_length.reference_length(60.0, 0.5)
    assert far.model == 'exact'
    assert 60.0 < far.length < 61.0


def test_scalar_and_vectorized_models_agree() -> None:
    rng = np.random.default_rng(8)
    dr = rng.uniform(0.0, 80.0, 300)
    dz = rng.uniform(-5.0, 60.0, 300)
    lengths, names = reference_length.reference_lengths(dr, dz)
    for a, b, length, name in zip(dr, dz, lengths, names, strict=True):
        point = reference_length.reference_length(a, b)
        assert point.model == name
        assert point.length == pytest.approx(length, rel=1e-10)


def test_exact_mode_is_the_heave_robust_length() -> None:
    result = reference_length.reference_length(12.0, 30.0, mode='exact')
    assert result.model == 'exact'
    assert result.length == pytest.approx(
        float(heave_robustness.robust_length(12.0, 30.0, 0.05).length), rel=1e-11)


def test_poly_vs_exact_over_the_operating_envelope() -> None:
    # Envelope Δz 2-60 m, Δr/Δz 0-2 (see `tethersim catenary reference`).
    dz, ratio = np.meshgrid(np.linspace(2.0, 60.0, 30), np.linspace(0.0, 2.0, 81), indexing='ij')
    model, names = reference_length.reference_lengths(ratio * dz, dz)
    exact = heave_robustness.robust_length(ratio * dz, dz, 0.05).length
    rel = np.abs(model / exact - 1.0)
    assert np.max(rel[names == 'poly3']) < 0.004
    assert np.max(rel) < 0.01


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match='mode'):
        reference_length.reference_length(1.0, 2.0, mode='table')
    with pytest.raises(ValueError, match='dr >= 0'):
        reference_length.reference_length(-1.0, 2.0)
