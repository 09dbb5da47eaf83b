"""Static catenary between the reel (point A) and the UAV (point B), thesis Sec. 3.1.1.

A tether of length ``L`` and linear density ``λ`` hangs between the reel at the origin and
the UAV at horizontal distance ``Δr ≥ 0`` and height ``Δz`` (positive when the UAV is above
the reel; level and below are allowed). Its shape is the catenary Eq. 3.2,
``z = z0 + a cosh((r - r0)/a)``, whose parameter ``a = T0/(λ g)`` (Eq. 3.3) solves the
transcendental Eq. 3.4, ``sqrt(L² - Δz²) = 2a sinh(Δr/(2a))``.

The solver works with two dimensionless numbers that keep every formula well conditioned:

* ``u = Δr/(2a)``, the root of ``sinh(u)/u = sqrt(L² - Δz²)/Δr`` (Eq. 3.4 rewritten);
  ``u → 0`` for a taut tether, ``u → ∞`` for a vertical hang (``Δr = 0``);
* ``m = artanh(Δz/L)``, so that the shift of Eq. 3.7 is ``r0 = a (u - m)``.

The slopes at the ends are then ``sinh(m - u)`` at A and ``sinh(m + u)`` at B (Eq. 3.9),
and the end tensions ``T = T0 cosh(·)`` (Eq. 3.11, 3.12). Everything is vectorized over
broadcastable arrays of ``(Δr, Δz, L)``; the vertical hang is the exact limit ``u → ∞``.

References:
    K. Talke, "Hanging Tether Management for Unmanned Air-Surface Vehicle Teams", PhD thesis,
    UC San Diego, 2021, Sec. 3.1.1, Eq. 3.2-3.12.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tether_models.constants import GRAVITY

THESIS_LINEAR_DENSITY = 0.042
"""Tether linear density λ (kg/m) of the thesis's flying-space analysis (Sec. 3.2.1)."""

_SERIES_LIMIT = 0.5
_LN2 = math.log(2.0)
_MAX_NEWTON = 60


def _sinhc_series(y):
    """``sinh(u)/u - 1`` for ``y = u²`` by its Taylor series, full relative precision for ``u < 0.5``."""
    return y / 6.0 * (1.0 + y / 20.0 * (1.0 + y / 42.0 * (1.0 + y / 72.0 * (
        1.0 + y / 110.0 * (1.0 + y / 156.0 * (1.0 + y / 210.0))))))


def _log_sinhc_slope_series(u, y):
    """``d/du ln(sinh(u)/u) = coth(u) - 1/u`` for ``y = u²`` by its Taylor series (``u < 0.5``)."""
    return u / 3.0 * (1.0 - y / 15.0 * (1.0 - 2.0 * y / 21.0 * (1.0 - 3.0 * y / 20.0 * (1.0 - 10.0 * y / 99.0))))


def sinhc_minus_one(u: np.ndarray) -> np.ndarray:
    """Return ``sinh(u)/u - 1`` to full relative precision for ``u ≥ 0`` (series below 0.5)."""
    small = u < _SERIES_LIMIT
    us = np.where(small, u, 0.0)
    ub = np.where(small, 1.0, np.minimum(u, 700.0))
    return np.where(small, _sinhc_series(us * us), np.sinh(ub) / ub - 1.0)


def _newton_step(u: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Newton step for ``ln(sinh(u)/u) = target``, value and slope in one pass, ``u > 0``.

    Below 0.5 both come from their Taylor series (full relative precision as ``u → 0``);
    above, from ``e = exp(-2u)``: ``ln(sinh(u)/u) = u + ln(1 - e) - ln 2 - ln u`` and
    ``coth(u) - 1/u = (1 + e)/(1 - e) - 1/u``, which never overflow.
    """
    small = u < _SERIES_LIMIT
    us = np.where(small, u, 0.0)
    y = us * us
    h_series = _sinhc_series(y)
    d_series = _log_sinhc_slope_series(us, y)
    ub = np.where(small, 1.0, u)
    e = np.exp(-2.0 * ub)
    value = np.where(small, np.log1p(h_series), ub + np.log1p(-e) - _LN2 - np.log(ub))
    slope = np.where(small, d_series, (1.0 + e) / (1.0 - e) - 1.0 / ub)
    return (value - target) / slope


def _initial_guess(q: np.ndarray) -> np.ndarray:
    """Starting point for :func:`inverse_sinhc`, within 6 % of the root for any excess.

    Small excess: the inverted series ``u² = 6q - 1.8q² + 0.822857q³``; large: the
    asymptotic ``u ≈ ln(2ρ) + ln(ln(2ρ) + ln(ln(2ρ)))`` with ``ρ = 1 + q``.
    """
    qs = np.minimum(q, 2.0)
    series = np.sqrt(6.0 * qs * np.where(qs < 0.5, 1.0 - qs * (0.3 - 0.137143 * qs),
                                         1.0 - 0.3 * np.minimum(qs, 1.0)))
    log_ratio = np.log(2.0 + 2.0 * np.maximum(q, 2.0))
    return np.where(q < 2.0, series, log_ratio + np.log(log_ratio + np.log(log_ratio)))


def inverse_sinhc(excess: np.ndarray) -> np.ndarray:
    """Solve ``sinh(u)/u = 1 + excess`` for ``u ≥ 0`` (the kernel of Eq. 3.4 and Eq. 3.13).

    ``excess`` is passed separately from the ratio so that nearly taut tethers (tiny
    excess) keep full relative precision. ``excess = inf`` gives ``u = inf``.

    Newton's method on ``ln(sinh(u)/u) - ln(1 + excess)``, a convex increasing function
    of ``u``: after the first step every iterate lies above the root and decreases
    monotonically to it.
    """
    q = np.asarray(excess, dtype=float)
    if np.any(q < 0.0):
        msg = 'inverse_sinhc needs a non-negative excess'
        raise ValueError(msg)
    infinite = np.isinf(q)
    zero = q == 0.0
    qq = np.where(infinite | zero, 1.0, q)
    target = np.log1p(qq)
    u = _initial_guess(qq)
    for _ in range(_MAX_NEWTON):
        step = _newton_step(u, target)
        u = np.maximum(u - step, 0.5 * u)
        # Quadratic convergence: the error left after a step of 1e-8 u is ~1e-16 u.
        if np.all(np.abs(step) <= 1e-8 * u):
            break
    else:
        msg = 'inverse_sinhc: Newton iteration did not converge'
        raise RuntimeError(msg)
    return np.where(infinite, np.inf, np.where(zero, 0.0, u))


def chord_length(dr: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """Return the straight-line (taut) distance between reel and UAV (m)."""
    return np.hypot(dr, dz)


def _check_lengths(dr: np.ndarray, length: np.ndarray, chord: np.ndarray) -> None:
    if np.any(dr < 0.0):
        msg = f'horizontal distance dr must be >= 0 (got min {np.min(dr):.6g} m)'
        raise ValueError(msg)
    if np.any(~np.isfinite(length)):
        msg = 'tether length L must be finite'
        raise ValueError(msg)
    short = length < chord * (1.0 - 4e-16)
    if np.any(short):
        i = np.flatnonzero(short.ravel())[0]
        msg = (f'tether length L = {length.ravel()[i]:.9g} m is shorter than the chord '
               f'{chord.ravel()[i]:.9g} m between reel and UAV: no catenary exists')
        raise ValueError(msg)


@dataclass(frozen=True)
class CatenarySolution:
    """Solved catenary between reel A = (0, 0) and UAV B = (Δr, Δz), Eq. 3.2-3.12.

    All fields are arrays of the broadcast shape of the inputs.

    Attributes:
        dr, dz, length: horizontal and vertical UAV offset and tether length (m).
        linear_density: λ (kg/m).  gravity : g (m/s²).
        u: Δr/(2a), root of Eq. 3.4 (0 taut, inf vertical hang).
        m: artanh(Δz/L).
        a: catenary parameter T0/(λ g) (m), Eq. 3.3; 0 for a vertical hang, inf when taut.
        r0, z0: shifts of Eq. 3.7 and Eq. 3.8 (vertex at (r0, z0 + a)), NaN when undefined.
        alpha: departure angle at the reel above the horizontal (rad), Eq. 3.9.
        beta: arrival angle at the UAV above the horizontal (rad), Eq. 3.9.
        horizontal_tension: T0 (N).
        tension_a, tension_b: end tensions at reel and UAV (N), Eq. 3.11, 3.12.
        lowest_r, lowest_z: the lowest point of the tether (m): the vertex if it lies
            between the ends, else the lower end.
    """

    dr: np.ndarray
    dz: np.ndarray
    length: np.ndarray
    linear_density: float
    gravity: float
    u: np.ndarray
    m: np.ndarray
    a: np.ndarray
    r0: np.ndarray
    z0: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    horizontal_tension: np.ndarray
    tension_a: np.ndarray
    tension_b: np.ndarray
    lowest_r: np.ndarray
    lowest_z: np.ndarray

    def residual(self) -> np.ndarray:
        """Return the relative residual of Eq. 3.4, ``|2a sinh(Δr/2a) - S| / S``."""
        chord = chord_length(self.dr, self.dz)
        s = np.sqrt(self.dr**2 + (self.length - chord) * (self.length + chord))
        with np.errstate(invalid='ignore', divide='ignore'):
            # 2a sinh(Δr/2a) = Δr sinh(u)/u = Δr (1 + excess(u))
            lhs_minus_s = self.dr * (1.0 + sinhc_minus_one(self.u)) - s
            res = np.abs(lhs_minus_s) / s
        vertical = (self.dr == 0.0) | (s == 0.0) | ~np.isfinite(self.u)
        return np.where(vertical, 0.0, res)

    def shape(self, n: int = 101) -> tuple[np.ndarray, np.ndarray]:
        """Return ``(r, z)`` of ``n`` points evenly spaced in arc length from A to B (Eq. 3.2).

        The output arrays have shape ``(*batch, n)`` (:func:`_shape`).
        """
        return _shape(self.dr, self.dz, self.length, self.u, self.m, self.a, n)


def _shape(dr: np.ndarray, dz: np.ndarray, length: np.ndarray, u: np.ndarray, m: np.ndarray, a: np.ndarray,
           n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(r, z)`` of ``n`` points evenly spaced in arc length along the catenaries of :func:`solve`'s
    ``u``, ``m`` and ``a`` (Eq. 3.2), shape ``(*batch, n)``.

    The point at arc length ``s`` from A has slope ``sinh(m - u) + s/a`` (Eq. 3.1); positions
    follow in closed form, written as products of sinh so that nearly taut tethers (``a → ∞``)
    stay exact.
    """
    s = np.linspace(0.0, 1.0, n) * length[..., None]
    u = u[..., None]
    m = m[..., None]
    a = a[..., None]
    finite = np.isfinite(u) & (u > 0.0)
    uf = np.where(finite, u, 1.0)
    af = np.where(finite, a, 1.0)
    # Angle variable w = asinh(slope): w(s) - w(0) from the exact subtraction formula.
    p0 = m - uf
    t0 = np.sinh(p0)
    t = t0 + s / af
    dw = np.arcsinh(t * np.cosh(p0) - t0 * np.sqrt(1.0 + t * t))
    r_cat = af * dw
    z_cat = 2.0 * af * np.sinh(p0 + 0.5 * dw) * np.sinh(0.5 * dw)
    # Vertical hang (Δr = 0): down from A to the lowest point, then up to B.
    depth = 0.5 * (length - np.abs(dz))[..., None]
    low = np.minimum(0.0, dz[..., None]) - depth
    z_vert = np.where(s <= -low, -s, low + (s + low))
    z_vert = np.where(dz[..., None] == length[..., None], s, z_vert)
    z_vert = np.where(-dz[..., None] == length[..., None], -s, z_vert)
    # Taut (u = 0): the straight chord.
    frac = s / length[..., None]
    taut = u == 0.0
    r = np.where(finite, r_cat, np.where(taut, frac * dr[..., None], 0.0))
    z = np.where(finite, z_cat, np.where(taut, frac * dz[..., None], z_vert))
    return r, z


def solve(dr: np.ndarray | float, dz: np.ndarray | float, length: np.ndarray | float,
          linear_density: float = THESIS_LINEAR_DENSITY,
          gravity: float = GRAVITY) -> CatenarySolution:
    """Solve the catenary for arrays of UAV offsets and tether lengths, Eq. 3.2-3.12.

    Parameters:
        dr: horizontal distance reel → UAV (m), ``≥ 0``.
        dz: height of the UAV above the reel (m); negative when below.
        length: tether length (m), at least the chord ``hypot(dr, dz)``.
        linear_density: λ (kg/m).
        gravity: g (m/s²).

    Raises:
        ValueError: A length shorter than the chord (no catenary exists), or a negative ``dr``.
    """
    dr, dz, length = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (dr, dz, length)))
    shape = dr.shape
    dr, dz, length = (v.reshape(-1) for v in (dr, dz, length))
    chord = chord_length(dr, dz)
    _check_lengths(dr, length, chord)
    length = np.maximum(length, chord)
    lg = linear_density * gravity
    # S = sqrt(L² - Δz²) = sqrt(Δr² + (L - c)(L + c)) and the excess
    # S/Δr - 1 = (L - c)(L + c) / ((S + Δr) Δr) of Eq. 3.4, both exact for nearly taut tethers.
    s = np.sqrt(dr * dr + (length - chord) * (length + chord))
    vertical = dr == 0.0
    drv = np.where(vertical, 1.0, dr)
    excess = (length - chord) * (length + chord) / ((s + drv) * drv)
    u = inverse_sinhc(np.where(vertical, np.inf, excess))
    taut = u == 0.0
    special = vertical | taut
    any_special = bool(np.any(special))
    # m = artanh(Δz/L), Eq. 3.7 as r0 = a (u - m)
    with np.errstate(divide='ignore'):
        m = np.arctanh(np.clip(dz / length, -1.0, 1.0))
    uc = np.where(special, 1.0, u) if any_special else u
    mc = np.where(special, 0.0, m) if any_special else m
    a = dr / (2.0 * uc)  # Eq. 3.3-3.4: Δr = 2 a u
    # Eq. 3.9: arctan(sinh(x)) is the Gudermannian 2 arctan(tanh(x/2)), finite for any x
    alpha = 2.0 * np.arctan(np.tanh(0.5 * (mc - uc)))
    beta = 2.0 * np.arctan(np.tanh(0.5 * (mc + uc)))
    # Eq. 3.11, 3.12 with T0 = λ g a: T = λ g S cosh(m ± u) / (2 sinh u), written with
    # exponentials that stay finite as u → ∞ (vertical hang) and exact as u → 0.
    decay = np.exp(-2.0 * uc)
    half_s = 0.5 * lg * s / -np.expm1(-2.0 * uc)
    e_m = np.exp(mc)
    tension_a = half_s * (e_m * decay + 1.0 / e_m)
    tension_b = half_s * (e_m + decay / e_m)
    horizontal_tension = lg * a
    # Eq. 3.7, 3.8 with A at the origin: r0 = a (u - m), z0 = -a cosh(m - u).
    r0 = a * (uc - mc)
    z0 = -a * np.cosh(mc - uc)
    # Lowest point: the vertex if 0 < r0 < Δr, i.e. |m| < u, at height
    # z0 + a = -2a sinh²((m - u)/2) (no cancellation of a against a cosh(·)); else the lower end.
    interior = np.abs(mc) < uc
    lowest_r = np.where(interior, r0, np.where(dz < 0.0, dr, 0.0))
    lowest_z = np.where(interior, -2.0 * a * np.sinh(0.5 * (mc - uc)) ** 2, np.minimum(dz, 0.0))
    if any_special:
        # Taut: the chord, infinite tension (inextensible tether).
        chord_angle = np.arctan2(dz[taut], dr[taut])
        alpha[taut] = chord_angle
        beta[taut] = chord_angle
        for field_ in (a, tension_a, tension_b, horizontal_tension):
            field_[taut] = np.inf
        # Vertical hang: the tether doubles down below the lower end (or is straight, L = |Δz|).
        dzv, lv = np.asarray(dz)[vertical], np.asarray(length)[vertical]
        lowest_vert = np.minimum(0.0, dzv) - 0.5 * (lv - np.abs(dzv))
        up, down = dzv == lv, -dzv == lv
        alpha[vertical] = np.where(up, 0.5 * np.pi, -0.5 * np.pi)
        beta[vertical] = np.where(down, -0.5 * np.pi, 0.5 * np.pi)
        tension_a[vertical] = np.where(up, 0.0, -lg * lowest_vert)
        tension_b[vertical] = np.where(down, 0.0, lg * (dzv - lowest_vert))
        a[vertical] = 0.0
        horizontal_tension[vertical] = 0.0
        lowest_r[vertical] = 0.0
        lowest_z[vertical] = lowest_vert
        r0[special] = np.nan
        z0[special] = np.nan
        lowest_r[taut] = np.where(dz[taut] < 0.0, dr[taut], 0.0)
        lowest_z[taut] = np.minimum(dz[taut], 0.0)
    fields = {'dr': dr, 'dz': dz, 'length': length, 'u': u, 'm': m, 'a': a, 'r0': r0,
              'z0': z0, 'alpha': alpha, 'beta': beta, 'horizontal_tension': horizontal_tension,
              'tension_a': tension_a, 'tension_b': tension_b, 'lowest_r': lowest_r,
              'lowest_z': lowest_z}
    return CatenarySolution(linear_density=linear_density, gravity=gravity,
                            **{k: v.reshape(shape) for k, v in fields.items()})


def sinhc_minus_one_point(u: float) -> float:
    """Scalar form of :func:`sinhc_minus_one`."""
    if u < _SERIES_LIMIT:
        return _sinhc_series(u * u)
    return math.sinh(u) / u - 1.0


def _newton_step_point(u: float, target: float) -> float:
    if u > 20.0:
        f = u - math.log(2.0 * u) + math.log1p(-math.exp(-2.0 * u)) - target
        return f / (1.0 / math.tanh(u) - 1.0 / u)
    f = math.log1p(sinhc_minus_one_point(u)) - target
    if u < _SERIES_LIMIT:
        return f / _log_sinhc_slope_series(u, u * u)
    return f / (1.0 / math.tanh(u) - 1.0 / u)


def inverse_sinhc_point(excess: float) -> float:
    """Scalar form of :func:`inverse_sinhc` for controller-rate use (``math`` only)."""
    if excess == 0.0:
        return 0.0
    if math.isinf(excess):
        return math.inf
    target = math.log1p(excess)
    if excess < 2.0:
        u = math.sqrt(6.0 * excess * (1.0 - 0.3 * min(excess, 1.0)))
    else:
        log_ratio = math.log(2.0 + 2.0 * excess)
        u = log_ratio + math.log(log_ratio)
    for _ in range(_MAX_NEWTON):
        step = _newton_step_point(u, target)
        u = max(u - step, 0.5 * u)
        if abs(step) <= 1e-8 * u:
            return u
    msg = 'inverse_sinhc_point: Newton iteration did not converge'
    raise RuntimeError(msg)


def point_parameters(dr: float, dz: float, length: float) -> tuple[float, float, float]:
    """Scalar Eq. 3.4 for :func:`tension_b_point`, :func:`shape_point` and the quasi-static plant's end
    tensions: the length (raised to the chord where rounding left it below), ``S = sqrt(L² - Δz²)``
    and ``u`` (inf for a vertical hang, 0 for a taut tether), as :func:`solve` computes them.

    Raises:
        ValueError: A length shorter than the chord, or a negative ``dr``.
    """
    chord = math.hypot(dr, dz)
    if dr < 0.0 or length < chord * (1.0 - 4e-16):
        msg = (f'tether length L = {length:.9g} m is shorter than the chord {chord:.9g} m '
               f'(or dr = {dr:.6g} m < 0)')
        raise ValueError(msg)
    length = max(length, chord)
    s = math.sqrt(dr * dr + (length - chord) * (length + chord))
    if dr == 0.0:
        return length, s, math.inf
    return length, s, inverse_sinhc_point((length - chord) * (length + chord) / ((s + dr) * dr))


def shape_point(dr: float, dz: float, length: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Scalar :func:`solve` and :meth:`CatenarySolution.shape`: ``(r, z)`` of ``n`` points of one
    catenary, its parameters on ``math`` paths (:func:`inverse_sinhc_point`), without
    :func:`solve`'s numpy work on a batch of one (about 300 µs here): the same points to rounding
    away from a vertical hang (:func:`tether_dynamics.plant.quasi_static.shape_points`).
    """
    length, _, u = point_parameters(dr, dz, length)
    ratio = dz / length
    m = math.atanh(ratio) if abs(ratio) < 1.0 else math.copysign(math.inf, ratio)
    a = 0.0 if math.isinf(u) else math.inf if u == 0.0 else dr / (2.0 * u)  # Eq. 3.3-3.4
    return _shape(np.asarray(dr), np.asarray(dz), np.asarray(length), np.asarray(u), np.asarray(m), np.asarray(a), n)


def tension_b_point(dr: float, dz: float, length: float,
                    linear_density: float = THESIS_LINEAR_DENSITY,
                    gravity: float = GRAVITY) -> float:
    """Scalar tension at the UAV (N), Eq. 3.4 and Eq. 3.12, as :func:`solve` computes it.

    A ``math``-only path, about 50 times faster than :func:`solve` on one point; used by
    the controller-rate reference length. Returns ``inf`` for a taut tether.
    """
    return tension_b_from_parameters(dr, dz, *point_parameters(dr, dz, length), linear_density * gravity)


def tension_b_from_parameters(dr: float, dz: float, length: float, s: float, u: float, lg: float) -> float:
    """Eq. 3.12: the tension at the UAV (N) from :func:`point_parameters`' length, S and u, for a
    weight per length ``lg`` (N/m); ``inf`` for a taut tether.
    """
    if dr == 0.0:
        return 0.0 if -dz == length else 0.5 * lg * (length + dz)
    if u == 0.0:
        return math.inf
    m = math.atanh(dz / length)
    return 0.5 * lg * s * (math.exp(m) + math.exp(-m - 2.0 * u)) / -math.expm1(-2.0 * u)
