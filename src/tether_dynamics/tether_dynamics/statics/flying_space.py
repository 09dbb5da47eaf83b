"""Flying-space analysis and its polynomial fits, thesis Sec. 3.2-3.3 (Eq. 3.16-3.19).

The thesis sweeps every relative position ``(Δx, Δy)`` of a grid (0.5 m steps to 60 m,
14,400 pairs) through 480 tether lengths between taut and beyond the minimum-tension
length, and reads off per pair: the minimum-tension length ``L_Tmin``, the slack length
(last length with departure angle ``α ≥ 0``), and the heave-robust lengths ``L_rob`` for
a 5, 10, 20 % tension rise by the shooting method over the same discrete lengths. Scaled
by ``Δy`` (Eq. 3.16), all pairs fall on single curves of ``Δx/Δy``, fitted by
Eq. 3.17 (tension), Eq. 3.18 (length) and Eq. 3.19 (departure angle).

:func:`sweep` is that brute-force analysis, vectorized in chunks; :func:`fit_tables`
fits the curves and :data:`THESIS_TABLES` holds Tables 3.1-3.3 for comparison. The
exact (root-found) values of the same quantities come from :mod:`heave_robustness` and
:func:`min_tension_length`; the sweep's discretization error is their difference.

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 3.2-3.3, Tables 3.1-3.3, Fig. 3.3-3.8.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tether_common.golden_section import golden_section_minimum
from tether_dynamics.statics import catenary, heave_robustness, reference_length
from tether_models.constants import GRAVITY

RISES = (0.05, 0.10, 0.20)
"""Tension rises over the slack tension that define L_rob5, L_rob10, L_rob20."""

N_LENGTHS = 480
"""Tether lengths per relative position in the thesis's sweep (Sec. 3.2.1)."""

MAX_LENGTH_FACTOR = 2.0
"""Sweep upper end: chord + this factor × (L_Tmin - chord); the thesis only says "large
enough to capture the minimum tension length" (its Fig. 3.3 example is ≈ 1.94)."""

FIT_RATIO_MAX = 1.1
"""Largest Δx/Δy used in the fits. The thesis does not state it; fitting the purely
geometric taut angle over the 0.5 m grid with Δx/Δy ≤ 1.1 reproduces Table 3.3's α_taut
row to all four decimals (1.0 or 1.2 do not), and Sec. 4.3 uses Eq. 4.4 up to 1.1."""

COMPARE_RATIO_MAX = 1.2
"""Fitted curves are compared over Δx/Δy ∈ [0, 1.2], the range the thesis claims (Sec. 3.5)."""


# Tables 3.1-3.3: name → (coefficients c1..cn in ascending powers of Δx/Δy, R²).
THESIS_TABLES: dict[str, dict[str, tuple[tuple[float, ...], float]]] = {
    'tension': {  # Table 3.1, T/(λ Δy) for λ = 1 (N·m/kg)
        'T_min': ((9.7864, 2.0294, 3.3904, -0.9513), 1.0),
        'T_slack': ((9.7886, 2.0226, 3.8953, 0.1676), 1.0),
        'T_rob5': ((9.8038, 2.5078, 3.5501, 0.3644), 1.0),
        'T_rob10': ((9.7940, 2.8427, 3.4364, 0.4404), 1.0),
        'T_rob20': ((9.7838, 3.1106, 3.7257, 0.3463), 1.0),
    },
    'length': {  # Table 3.2, L/Δy
        'L_min': ((0.9972, 0.2406, 0.5849, -0.1497), 1.0),
        'L_slack': ((0.9976, 0.2094, 0.3752, -0.0862), 1.0),
        'L_rob5': (reference_length.POLY3, 1.0),  # Eq. 4.4 repeats this row
        'L_rob10': ((0.9974, 0.1283, 0.4888, -0.1335), 1.0),
        'L_rob20': ((0.9982, 0.1127, 0.4906, -0.12831), 1.0),
    },
    'angle': {  # Table 3.3, α in degrees
        'alpha_min': ((-10.0482, -49.6974, 36.8857, -13.2127), 0.99),
        'alpha_taut': ((90.3299, -62.0733, 16.7069), 1.0),
        'alpha_rob5': ((40.3217, -162.7497, 309.9161, -280.6729, 95.8555), 0.99),
        'alpha_rob10': ((40.5363, -105.5804, 116.5771, -46.5409), 0.99),
        'alpha_rob20': ((41.6537, -84.6802, 79.7592, -28.9605), 0.99),
    },
}


def grid(step: float = 0.5, extent: float = 60.0) -> tuple[np.ndarray, np.ndarray]:
    """Return flat arrays ``(Δx, Δy)`` of the grid ``(0, extent]²`` in ``step`` (Sec. 3.2.1)."""
    if step <= 0.0 or extent < step:
        msg = f'grid needs 0 < step <= extent (got step {step}, extent {extent})'
        raise ValueError(msg)
    axis = step * np.arange(1, int(round(extent / step)) + 1)
    dx, dy = np.meshgrid(axis, axis, indexing='ij')
    return dx.ravel(), dy.ravel()


def min_tension_length(dr: np.ndarray, dz: np.ndarray, iterations: int = 90,
                       linear_density: float = catenary.THESIS_LINEAR_DENSITY,
                       gravity: float = GRAVITY) -> np.ndarray:
    """Return the length minimizing the UAV tension T_B (m), by golden-section search.

    T_B(L) (Eq. 3.12) falls steeply from the taut chord and rises slowly beyond the
    minimum (Fig. 3.4); the search runs over ``[chord, 2 chord]`` for every pair at once.
    """
    dr, dz = np.broadcast_arrays(np.asarray(dr, dtype=float), np.asarray(dz, dtype=float))
    lo = catenary.chord_length(dr, dz)
    hi = 2.0 * lo

    def tension(length: np.ndarray) -> np.ndarray:
        return catenary.solve(dr, dz, length, linear_density, gravity).tension_b

    return golden_section_minimum(tension, lo, hi, iterations)


@dataclass
class SweepResult:
    """Per-pair results of the thesis's discrete sweep (arrays over the pairs).

    ``rob_*`` hold one array per tension rise of :data:`RISES`, in that order.
    """

    dx: np.ndarray
    dy: np.ndarray
    n_lengths: int
    length_min: np.ndarray
    tension_min: np.ndarray
    alpha_min: np.ndarray
    length_slack: np.ndarray
    tension_slack: np.ndarray
    alpha_slack: np.ndarray
    alpha_taut: np.ndarray
    rob_length: list[np.ndarray] = field(default_factory=list)
    rob_heave: list[np.ndarray] = field(default_factory=list)
    rob_tension: list[np.ndarray] = field(default_factory=list)
    rob_alpha: list[np.ndarray] = field(default_factory=list)

    @property
    def ratio(self) -> np.ndarray:
        """Return the nondimensional offset Δx/Δy of Eq. 3.16."""
        return self.dx / self.dy


def sweep_lengths(dx: np.ndarray, dy: np.ndarray, n_lengths: int = N_LENGTHS,
                  linear_density: float = catenary.THESIS_LINEAR_DENSITY,
                  gravity: float = GRAVITY) -> np.ndarray:
    """Return the ``(pairs, n_lengths)`` lengths from the taut chord to beyond L_Tmin."""
    chord = catenary.chord_length(dx, dy)
    l_max = chord + MAX_LENGTH_FACTOR * (
        min_tension_length(dx, dy, linear_density=linear_density, gravity=gravity) - chord)
    return chord[:, None] + (l_max - chord)[:, None] * np.linspace(0.0, 1.0, n_lengths)


def _sweep_chunk(dx: np.ndarray, dy: np.ndarray, n_lengths: int, linear_density: float,
                 gravity: float) -> dict[str, np.ndarray]:
    lengths = sweep_lengths(dx, dy, n_lengths, linear_density, gravity)
    dx2, dy2 = dx[:, None], dy[:, None]
    nominal = catenary.solve(dx2, dy2, lengths, linear_density, gravity)
    rows = np.arange(dx.size)
    k_min = np.argmin(nominal.tension_b, axis=1)
    # Slack: the last (longest) swept length whose departure angle is still >= 0.
    k_slack = np.maximum(np.sum(nominal.alpha >= 0.0, axis=1) - 1, 1)
    out = {
        'length_min': lengths[rows, k_min],
        'tension_min': nominal.tension_b[rows, k_min],
        'alpha_min': nominal.alpha[rows, k_min],
        'length_slack': lengths[rows, k_slack],
        'tension_slack': nominal.tension_b[rows, k_slack],
        'alpha_slack': nominal.alpha[rows, k_slack],
        'alpha_taut': nominal.alpha[:, 0],
    }
    # Shooting method (Sec. 3.1.2) on the same lengths: upward limit Δy1 (Eq. 3.13-3.14),
    # then the UAV tension with the reel lowered by Δy2 = Δy1 (Eq. 3.15, 3.12).
    below_slack = np.arange(n_lengths)[None, :] <= k_slack[:, None]
    l_up = np.where(below_slack, lengths, np.maximum(lengths, dx2))
    heave = heave_robustness.upward_heave_limit(dx2, dy2, l_up)
    dy_low = dy2 + np.where(below_slack, heave, 0.0)
    reachable = below_slack & (lengths > np.hypot(dx2, dy_low))
    t_low = catenary.solve(dx2, dy_low, np.where(reachable, lengths, 2.0 * np.hypot(dx2, dy_low)),
                           linear_density, gravity).tension_b
    t_low = np.where(reachable, t_low, np.inf)
    for rise in RISES:
        limit = (1.0 + rise) * out['tension_slack']
        # Longest length at or below slack where the lowered tension reaches the limit.
        hits = below_slack & (t_low >= limit[:, None])
        k_rob = n_lengths - 1 - np.argmax(hits[:, ::-1], axis=1)
        out.setdefault('rob_length', []).append(lengths[rows, k_rob])
        out.setdefault('rob_heave', []).append(heave[rows, k_rob])
        out.setdefault('rob_tension', []).append(nominal.tension_b[rows, k_rob])
        out.setdefault('rob_alpha', []).append(nominal.alpha[rows, k_rob])
    return out


def sweep(dx: np.ndarray, dy: np.ndarray, n_lengths: int = N_LENGTHS,
          linear_density: float = catenary.THESIS_LINEAR_DENSITY,
          gravity: float = GRAVITY, chunk: int = 200,
          progress: Callable[[int, int], None] | None = None) -> SweepResult:
    """Run the thesis's brute-force sweep (Sec. 3.2) over the pairs ``(dx, dy)``.

    ``progress(done, total)`` is called after each chunk of ``chunk`` pairs.
    """
    dx = np.asarray(dx, dtype=float).ravel()
    dy = np.asarray(dy, dtype=float).ravel()
    if np.any(dx <= 0.0) or np.any(dy <= 0.0):
        msg = 'the flying-space sweep needs dx > 0 and dy > 0 (Sec. 3.2.1)'
        raise ValueError(msg)
    parts: list[dict[str, np.ndarray]] = []
    for start in range(0, dx.size, chunk):
        parts.append(_sweep_chunk(dx[start:start + chunk], dy[start:start + chunk],
                                  n_lengths, linear_density, gravity))
        if progress is not None:
            progress(min(start + chunk, dx.size), dx.size)
    merged: dict[str, Any] = {}
    for key, value in parts[0].items():
        if isinstance(value, list):
            merged[key] = [np.concatenate([p[key][i] for p in parts]) for i in range(len(value))]
        else:
            merged[key] = np.concatenate([p[key] for p in parts])
    return SweepResult(dx=dx, dy=dy, n_lengths=n_lengths, **merged)


@dataclass(frozen=True)
class Fit:
    """A least-squares polynomial in Δx/Δy (ascending coefficients) and its R²."""

    coefficients: np.ndarray
    r_squared: float

    def __call__(self, ratio: np.ndarray) -> np.ndarray:
        """Evaluate the polynomial at ``ratio``."""
        return np.polynomial.polynomial.polyval(ratio, self.coefficients)


def fit_curve(ratio: np.ndarray, values: np.ndarray, order: int,
              ratio_max: float = FIT_RATIO_MAX) -> Fit:
    """Least-squares fit of ``values`` by a polynomial of ``order`` in ``ratio ≤ ratio_max``."""
    use = (ratio <= ratio_max) & np.isfinite(values)
    x, y = ratio[use], values[use]
    coefficients = np.polynomial.polynomial.polyfit(x, y, order)
    residual = y - np.polynomial.polynomial.polyval(x, coefficients)
    r_squared = 1.0 - np.sum(residual**2) / np.sum((y - np.mean(y)) ** 2)
    return Fit(coefficients=coefficients, r_squared=float(r_squared))


def curve_data(result: SweepResult, linear_density: float) -> dict[str, dict[str, np.ndarray]]:
    """Return the nondimensional data of Tables 3.1-3.3: T/(λΔy), L/Δy, α (deg)."""
    dy = result.dy
    tension = {'T_min': result.tension_min, 'T_slack': result.tension_slack}
    length = {'L_min': result.length_min, 'L_slack': result.length_slack}
    angle = {'alpha_min': result.alpha_min, 'alpha_taut': result.alpha_taut}
    for rise, l_rob, t_rob, a_rob in zip(RISES, result.rob_length, result.rob_tension,
                                         result.rob_alpha, strict=True):
        tag = f'rob{round(100 * rise)}'
        tension[f'T_{tag}'] = t_rob
        length[f'L_{tag}'] = l_rob
        angle[f'alpha_{tag}'] = a_rob
    return {
        'tension': {k: v / (linear_density * dy) for k, v in tension.items()},
        'length': {k: v / dy for k, v in length.items()},
        'angle': {k: np.degrees(v) for k, v in angle.items()},
    }


def exact_curve_data(dx: np.ndarray, dy: np.ndarray, linear_density: float,
                     gravity: float = GRAVITY) -> dict[str, dict[str, np.ndarray]]:
    """Return the data of Tables 3.1-3.3 from root-found values instead of the sweep.

    L_Tmin by golden-section search, L_slack in closed form after one Newton solve,
    L_rob by the shooting-method root find (:mod:`heave_robustness`).
    """
    dx = np.asarray(dx, dtype=float)
    dy = np.asarray(dy, dtype=float)
    l_min = min_tension_length(dx, dy, linear_density=linear_density, gravity=gravity)
    at_min = catenary.solve(dx, dy, l_min, linear_density, gravity)
    tension = {'T_min': at_min.tension_b,
               'T_slack': heave_robustness.slack_tension(dx, dy, linear_density, gravity)}
    length = {'L_min': l_min, 'L_slack': heave_robustness.slack_length(dx, dy)}
    angle = {'alpha_min': at_min.alpha, 'alpha_taut': np.arctan2(dy, dx)}
    for rise in RISES:
        tag = f'rob{round(100 * rise)}'
        rob = heave_robustness.robust_length(dx, dy, rise, linear_density, gravity)
        tension[f'T_{tag}'] = rob.nominal.tension_b
        length[f'L_{tag}'] = rob.length
        angle[f'alpha_{tag}'] = rob.nominal.alpha
    return {
        'tension': {k: v / (linear_density * dy) for k, v in tension.items()},
        'length': {k: v / dy for k, v in length.items()},
        'angle': {k: np.degrees(v) for k, v in angle.items()},
    }


def fit_data(ratio: np.ndarray, data: dict[str, dict[str, np.ndarray]],
             ratio_max: float = FIT_RATIO_MAX) -> dict[str, dict[str, Fit]]:
    """Fit every row of Tables 3.1-3.3 with the thesis's polynomial order (Eq. 3.17-3.19)."""
    return {
        table: {name: fit_curve(ratio, values, len(THESIS_TABLES[table][name][0]) - 1, ratio_max)
                for name, values in rows.items()}
        for table, rows in data.items()
    }


def fit_tables(result: SweepResult, linear_density: float,
               ratio_max: float = FIT_RATIO_MAX) -> dict[str, dict[str, Fit]]:
    """Fit Tables 3.1-3.3 to the sweep's data, as the thesis did."""
    return fit_data(result.ratio, curve_data(result, linear_density), ratio_max)


def thesis_fit(table: str, name: str) -> Fit:
    """Return the thesis's fit for one row of Tables 3.1-3.3."""
    coefficients, r_squared = THESIS_TABLES[table][name]
    return Fit(coefficients=np.array(coefficients), r_squared=r_squared)


def max_curve_difference(a: Fit, b: Fit, ratio_max: float = COMPARE_RATIO_MAX,
                         ratio_min: float = 0.0) -> tuple[float, float]:
    """Return ``(max |a - b|, Δx/Δy where it occurs)`` over ``[ratio_min, ratio_max]``."""
    x = np.linspace(ratio_min, ratio_max, 2401)
    diff = np.abs(a(x) - b(x))
    i = int(np.argmax(diff))
    return float(diff[i]), float(x[i])


def heave_tolerance_curve(ratio: np.ndarray, rise: float) -> np.ndarray:
    """Return the nondimensional heave tolerance Δy₁/Δy at offsets ``ratio`` (exact, Fig. 3.5b)."""
    ratio = np.asarray(ratio, dtype=float)
    return heave_robustness.robust_length(ratio, np.ones_like(ratio), rise).heave


def recommended_ratio(rise: float = 0.05) -> tuple[float, float]:
    """Return ``(Δx/Δy, Δy₁/Δy)`` of the largest heave tolerance (thesis ≈ 0.46, Sec. 3.3.2).

    Exact: the tolerance of L_rob is maximized over Δx/Δy by a fine scan refined by
    golden-section search (the curve is smooth and unimodal, Fig. 3.5b).
    """
    coarse = np.linspace(0.01, 2.0, 400)
    i = int(np.argmax(heave_tolerance_curve(coarse, rise)))
    lo, hi = coarse[max(i - 1, 0)], coarse[min(i + 1, coarse.size - 1)]
    best = float(golden_section_minimum(lambda x: -heave_tolerance_curve(np.atleast_1d(x), rise).reshape(x.shape),
                                        lo, hi, 60))
    return best, float(heave_tolerance_curve(np.array([best]), rise)[0])
