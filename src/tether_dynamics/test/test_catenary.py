"""Tests of the catenary solver (thesis Eq. 3.2-3.12) against analytic limits and an ODE."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from tether_dynamics.statics import catenary
from tether_models.constants import GRAVITY

LG = catenary.THESIS_LINEAR_DENSITY * GRAVITY


def _random_cases(n: int = 4000, seed: int = 7) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Offsets over the reachable domain, lengths from 1e-12 over the chord to very slack."""
    rng = np.random.default_rng(seed)
    dr = rng.uniform(0.0, 60.0, n)
    dr[:50] = 0.0
    dz = rng.uniform(-60.0, 60.0, n)
    dz[50:100] = 0.0
    chord = np.hypot(dr, dz)
    length = chord * (1.0 + 10.0 ** rng.uniform(-12.0, 1.5, n))
    return dr, dz, length


def test_residual_of_eq_3_4_is_below_1e_12_everywhere() -> None:
    dr, dz, length = _random_cases()
    sol = catenary.solve(dr, dz, length)
    assert np.all(np.isfinite(sol.tension_b))
    assert np.max(sol.residual()) <= 1e-12


def test_inverse_sinhc_over_twenty_decades() -> None:
    excess = np.logspace(-15, 15, 301)
    u = catenary.inverse_sinhc(excess)
    np.testing.assert_allclose(catenary.sinhc_minus_one(u), excess, rtol=1e-13)


def test_force_balance_holds_for_every_solution() -> None:
    dr, dz, length = _random_cases(seed=11)
    keep = dr > 0.0
    sol = catenary.solve(dr[keep], dz[keep], length[keep])
    t_a, t_b = sol.tension_a, sol.tension_b
    scale = t_a + t_b
    # Vertical: the tether's weight; horizontal: T0 at both ends (Eq. 3.1, 3.11, 3.12).
    np.testing.assert_allclose((t_b * np.sin(sol.beta) - t_a * np.sin(sol.alpha)) / scale,
                               LG * length[keep] / scale, atol=1e-10)
    np.testing.assert_allclose(t_a * np.cos(sol.alpha), sol.horizontal_tension, rtol=1e-9)
    np.testing.assert_allclose(t_b * np.cos(sol.beta), sol.horizontal_tension, rtol=1e-9)
    # Tension grows with height along a catenary: T_B - T_A = λ g Δz.
    np.testing.assert_allclose((t_b - t_a) / scale, LG * dz[keep] / scale, atol=1e-10)


def test_vertical_hang_is_exact_and_the_limit_of_small_offsets() -> None:
    sol = catenary.solve(0.0, 20.0, 30.0)
    assert sol.tension_a == pytest.approx(LG * 5.0, rel=1e-14)
    assert sol.tension_b == pytest.approx(LG * 25.0, rel=1e-14)
    assert sol.lowest_z == pytest.approx(-5.0)
    assert sol.alpha == pytest.approx(-np.pi / 2)
    assert sol.beta == pytest.approx(np.pi / 2)
    near = catenary.solve(1e-7, 20.0, 30.0)
    assert near.tension_b == pytest.approx(sol.tension_b, rel=1e-6)
    assert near.tension_a == pytest.approx(sol.tension_a, rel=1e-6)
    assert near.lowest_z == pytest.approx(-5.0, abs=1e-6)


def test_vertical_taut_tether() -> None:
    sol = catenary.solve([0.0, 0.0], [20.0, -20.0], [20.0, 20.0])
    np.testing.assert_allclose(sol.tension_b, [LG * 20.0, 0.0])
    np.testing.assert_allclose(sol.tension_a, [0.0, LG * 20.0])


def test_symmetric_endpoints() -> None:
    sol = catenary.solve(30.0, 0.0, 40.0)
    assert sol.tension_a == pytest.approx(sol.tension_b, rel=1e-14)
    assert sol.alpha == pytest.approx(-sol.beta, rel=1e-14)
    assert sol.lowest_r == pytest.approx(15.0, rel=1e-14)
    # sag of the symmetric catenary: a (cosh(Δr/2a) - 1)
    assert -sol.lowest_z == pytest.approx(sol.a * (np.cosh(15.0 / sol.a) - 1.0), rel=1e-12)
    # and the closed form L = 2a sinh(Δr/2a)
    assert 2.0 * sol.a * np.sinh(15.0 / sol.a) == pytest.approx(40.0, rel=1e-14)


@pytest.mark.parametrize('excess', [1e-4, 1e-7, 1e-10])
def test_nearly_taut_matches_the_shallow_cable_limit(excess: float) -> None:
    # Level supports, L = Δr (1 + ε): u ≈ sqrt(6ε), T0 = λ g Δr / (2u) (1 + O(ε)).
    dr = 25.0
    length = dr * (1.0 + excess)
    excess = (length - dr) / dr  # the excess actually represented (L - Δr is exact)
    sol = catenary.solve(dr, 0.0, length)
    u = np.sqrt(6.0 * excess * (1.0 - 0.3 * excess))
    assert sol.horizontal_tension == pytest.approx(LG * dr / (2.0 * u), rel=10 * excess**2 + 1e-9)
    r, z = sol.shape(11)
    np.testing.assert_allclose(z, 0.0, atol=dr * np.sqrt(excess))


def test_length_shorter_than_chord_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match='shorter than the chord'):
        catenary.solve([10.0, 3.0], [5.0, 4.0], [20.0, 4.99])
    with pytest.raises(ValueError, match='shorter than the chord'):
        catenary.tension_b_point(3.0, 4.0, 4.99)
    with pytest.raises(ValueError, match='dr must be >= 0'):
        catenary.solve(-1.0, 4.0, 10.0)


def test_uav_level_or_below_the_reel() -> None:
    below = catenary.solve(20.0, -10.0, 30.0)
    above = catenary.solve(20.0, 10.0, 30.0)
    # Mirror symmetry: swapping the ends swaps the end tensions and the angles.
    assert below.tension_a == pytest.approx(above.tension_b, rel=1e-13)
    assert below.alpha == pytest.approx(-above.beta, rel=1e-13)
    assert below.lowest_z == pytest.approx(above.lowest_z - 10.0, rel=1e-12)


def test_scalar_path_agrees_with_the_vectorized_solver() -> None:
    dr, dz, length = _random_cases(n=500, seed=3)
    sol = catenary.solve(dr, dz, length)
    point = np.array([catenary.tension_b_point(*args)
                      for args in zip(dr, dz, length, strict=True)])
    # Agreement is limited by the conditioning of L - chord for nearly taut tethers.
    chord = np.hypot(dr, dz)
    tolerance = 1e-12 + 4e-16 * length / (length - chord)
    assert np.all(np.abs(point / sol.tension_b - 1.0) <= tolerance)


def test_shape_ends_at_the_uav_and_has_the_tether_length() -> None:
    dr, dz, length = _random_cases(n=300, seed=5)
    sol = catenary.solve(dr, dz, length)
    r, z = sol.shape(2001)
    assert np.all(np.abs(r[:, -1] - dr) <= 1e-9 * length)
    assert np.all(np.abs(z[:, -1] - dz) <= 1e-9 * length)
    arc = np.sum(np.hypot(np.diff(r), np.diff(z)), axis=1)
    np.testing.assert_allclose(arc, length, rtol=2e-3)
    assert np.all(z.min(axis=1) >= sol.lowest_z - 1e-9 * length)
    assert np.allclose(z.min(axis=1), sol.lowest_z, atol=5e-3 * length)


def _integrate_hanging_cable(dr: float, dz: float, length: float) -> tuple[float, float, object]:
    """Independent solve: shoot the ODE d(T sinφ)/ds = λg, T cosφ = T0 from the reel."""

    def rhs(_s: float, y: np.ndarray, t0: float) -> list[float]:
        phi = y[2]
        return [np.cos(phi), np.sin(phi), LG * np.cos(phi) ** 2 / t0]

    def end(params: np.ndarray) -> np.ndarray:
        t0, alpha = np.exp(params[0]), params[1]
        y = solve_ivp(rhs, (0.0, length), [0.0, 0.0, alpha], args=(t0,), rtol=1e-12,
                      atol=1e-12).y[:, -1]
        return np.array([y[0] - dr, y[1] - dz])

    guess = catenary.solve(dr, dz, length)
    start = np.array([np.log(guess.horizontal_tension) + 0.2, guess.alpha + 0.1])
    params = fsolve(end, start, xtol=1e-13)
    t0, alpha = float(np.exp(params[0])), float(params[1])
    dense = solve_ivp(rhs, (0.0, length), [0.0, 0.0, alpha], args=(t0,), rtol=1e-12,
                      atol=1e-12, dense_output=True)
    return t0, alpha, dense.sol


@pytest.mark.parametrize(('dr', 'dz', 'length'), [
    (20.0, 55.0, 63.4), (44.0, 55.0, 74.8), (10.0, -5.0, 14.0), (5.0, 0.0, 9.0)])
def test_against_independent_ode_integration(dr: float, dz: float, length: float) -> None:
    t0, alpha, shape = _integrate_hanging_cable(dr, dz, length)
    sol = catenary.solve(dr, dz, length)
    assert sol.horizontal_tension == pytest.approx(t0, rel=1e-7)
    assert sol.alpha == pytest.approx(alpha, abs=1e-7)
    r, z = sol.shape(41)
    s = np.linspace(0.0, length, 41)
    ode = shape(s)
    np.testing.assert_allclose(r, ode[0], atol=1e-6 * length)
    np.testing.assert_allclose(z, ode[1], atol=1e-6 * length)
