"""Tests of the flying-space sweep and fits against the thesis's Tables 3.1-3.3."""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.statics import catenary, flying_space, heave_robustness

LAMBDA = catenary.THESIS_LINEAR_DENSITY


@pytest.fixture(scope='module')
def sweep_result() -> flying_space.SweepResult:
    """The thesis's sweep on a 2.5 m grid (576 pairs × 480 lengths)."""
    dx, dy = flying_space.grid(2.5)
    return flying_space.sweep(dx, dy)


@pytest.fixture(scope='module')
def fits(sweep_result: flying_space.SweepResult) -> dict[str, dict[str, flying_space.Fit]]:
    return flying_space.fit_tables(sweep_result, LAMBDA)


def test_grid_matches_the_thesis_analysis_limits() -> None:
    dx, dy = flying_space.grid()
    assert dx.size == 14400
    assert dx.min() == 0.5
    assert dy.max() == 60.0
    with pytest.raises(ValueError, match='step'):
        flying_space.grid(0.0)


@pytest.mark.parametrize('name', ['L_min', 'L_slack', 'L_rob5', 'L_rob10', 'L_rob20'])
def test_length_fits_reproduce_table_3_2(fits: dict, name: str) -> None:
    # Done-criterion: within 1 % of L over Δx/Δy in [0.05, 1.2]. Reproduced on this 2.5 m
    # grid: <= 0.08 % (0.5 m grid, `analyze --full`: <= 0.05 %).
    x = np.linspace(0.05, 1.2, 231)
    ours = fits['length'][name](x)
    thesis = flying_space.thesis_fit('length', name)(x)
    assert np.max(np.abs(ours / thesis - 1.0)) < 0.002
    assert fits['length'][name].r_squared > 0.9999


@pytest.mark.parametrize('name', ['T_min', 'T_slack', 'T_rob5', 'T_rob10', 'T_rob20'])
def test_tension_fits_reproduce_table_3_1(fits: dict, name: str) -> None:
    # Reproduced on this grid: <= 0.33 % over [0.05, 1.2].
    x = np.linspace(0.05, 1.2, 231)
    ours = fits['tension'][name](x)
    thesis = flying_space.thesis_fit('tension', name)(x)
    assert np.max(np.abs(ours / thesis - 1.0)) < 0.005


@pytest.mark.parametrize(('name', 'degrees'), [
    ('alpha_taut', 0.1), ('alpha_min', 1.0), ('alpha_rob5', 1.5), ('alpha_rob10', 1.2),
    ('alpha_rob20', 1.0)])
def test_angle_fits_reproduce_table_3_3(fits: dict, name: str, degrees: float) -> None:
    # Reproduced on this grid within 1.1° (α_rob5 at Δx/Δy = 0).
    diff, _ = flying_space.max_curve_difference(fits['angle'][name],
                                                flying_space.thesis_fit('angle', name))
    assert diff < degrees


def test_exact_values_on_the_thesis_grid_reproduce_table_rows_to_four_decimals() -> None:
    # On the 0.5 m grid with Δx/Δy <= 1.1, the fits of the exact minimum-tension length and
    # tension and of the (geometric) taut angle equal the thesis's rows to 4 decimals: this
    # pins down the thesis's fit range, g = 9.81 and λ = 0.042 kg/m.
    dx, dy = flying_space.grid(0.5)
    use = dx / dy <= flying_space.FIT_RATIO_MAX
    dx, dy = dx[use], dy[use]
    ratio = dx / dy
    l_min = flying_space.min_tension_length(dx, dy)
    at_min = catenary.solve(dx, dy, l_min)
    cases = [('tension', 'T_min', at_min.tension_b / (LAMBDA * dy)),
             ('length', 'L_min', l_min / dy),
             ('angle', 'alpha_taut', np.degrees(np.arctan2(dy, dx)))]
    for table, name, values in cases:
        thesis = flying_space.thesis_fit(table, name)
        fit = flying_space.fit_curve(ratio, values, thesis.coefficients.size - 1)
        np.testing.assert_allclose(fit.coefficients, thesis.coefficients, atol=6e-5,
                                   err_msg=name)
    alpha_min = flying_space.fit_curve(ratio, np.degrees(at_min.alpha), 3)
    assert flying_space.max_curve_difference(
        alpha_min, flying_space.thesis_fit('angle', 'alpha_min'))[0] < 0.01


def test_sweep_agrees_with_the_exact_lengths(sweep_result: flying_space.SweepResult) -> None:
    dx, dy = sweep_result.dx, sweep_result.dy
    chord = np.hypot(dx, dy)
    step = flying_space.MAX_LENGTH_FACTOR * (flying_space.min_tension_length(dx, dy) - chord) / (
        sweep_result.n_lengths - 1)
    exact_slack = heave_robustness.slack_length(dx, dy)
    assert np.all(np.abs(sweep_result.length_slack - exact_slack) <= step * 1.0001)
    # L_rob also inherits the slack tension of the discrete slack length: within 1.5 steps.
    exact_rob = heave_robustness.robust_length(dx, dy, 0.05).length
    assert np.all(np.abs(sweep_result.rob_length[0] - exact_rob) <= 1.5 * step)
    assert np.max(np.abs(sweep_result.rob_length[0] / exact_rob - 1.0)) < 2e-3


def test_min_tension_length_for_level_ends_is_analytic() -> None:
    # Level ends: T_B = λ g Δr cosh(u)/(2u) is least where u tanh(u) = 1, L/Δr = sinh(u)/u.
    u = 1.19967864025773
    length = flying_space.min_tension_length(np.array([10.0]), np.array([0.0]))
    assert length[0] / 10.0 == pytest.approx(np.sinh(u) / u, rel=1e-8)


def test_recommended_ratio_near_thesis_value() -> None:
    # Thesis: ≈ 0.46 read from the sweep's scatter (Fig. 3.5b); the exact maximum is 0.479.
    ratio, tolerance = flying_space.recommended_ratio(0.05)
    assert ratio == pytest.approx(0.479, abs=0.002)
    assert abs(ratio - 0.46) < 0.025
    assert tolerance == pytest.approx(0.0125, abs=2e-4)
