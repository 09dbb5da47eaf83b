"""Quasi-static fidelity: the elastic catenary between guide way and UAV, solved each step.

The inextensible catenary of :mod:`tether_dynamics.statics.catenary` (Sec. 3.1.1) is solved
for the stretched length L_s, and L_s is found from the unstretched deployed length L by
L_s = L (1 + T_mean / EA), T_mean = (T_A + T_B) / 2 (exact for a vertical hang, where the
tension is linear in arc length, and within the square of the sag-to-span ratio otherwise),
with the stretched line density mu L / L_s so the hanging weight stays mu L g.
This keeps the model defined when the deployed length is shorter than the chord (a taut,
stretched tether) where the inextensible catenary has no solution. The root is bracketed
and found by Brent's method on scalars (``scipy.optimize.brentq``); T_A = T_B - mu g dz
holds exactly on a catenary.

:func:`tension_a_slope` gives dT_A/dL of this model in closed form by implicit
differentiation of L_s = L (1 + T_mean / EA), for the winch's tension between plant steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from tether_dynamics.statics import catenary

_VERTICAL_DR = 1e-12
"""A horizontal offset (m) up to which the tether hangs vertically."""
_TAUT_MARGIN = 1e-12
"""L_s stays at least (1 + this) times the chord: the inextensible catenary is defined there."""
_SLOPE_STEP = 1e-4
"""Relative step in L of :func:`tension_a_slope`'s central difference where its closed form fails."""
_MAX_NEWTON = 20
"""Newton steps :func:`tension_a_slope` takes before it falls back to the central difference."""
_ROOT_TOLERANCE = 1e-13
"""|F|/F_Ls, relative to L, at which the slope's Newton iteration has L_s."""
_MAX_U = 700.0
"""Largest u = dr/(2a) the slope's Newton iteration tries (sinh overflows past 710)."""


@dataclass(frozen=True)
class ElasticCatenary:
    """The solved shape between A (guide way) and B (UAV attachment) in 3-D.

    Attributes:
        solution: the inextensible catenary of the stretched length.
        stretched_length: L_s, m.  horizontal : (3,) unit horizontal direction A -> B.
    """

    solution: catenary.CatenarySolution
    stretched_length: float
    horizontal: np.ndarray

    @property
    def tension_a(self) -> float:
        """Tension at the guide way, N."""
        return float(self.solution.tension_a)

    @property
    def tension_b(self) -> float:
        """Tension at the UAV, N."""
        return float(self.solution.tension_b)

    def tangent_a(self) -> np.ndarray:
        """Unit tangent at A pointing along the tether towards B."""
        a = float(self.solution.alpha)
        return math.cos(a) * self.horizontal + np.array([0.0, 0.0, math.sin(a)])

    def tangent_b(self) -> np.ndarray:
        """Unit tangent at B pointing away from A (along the tether, beyond the UAV)."""
        b = float(self.solution.beta)
        return math.cos(b) * self.horizontal + np.array([0.0, 0.0, math.sin(b)])

    def points(self, a: np.ndarray, n: int) -> np.ndarray:
        """n points from A to B evenly spaced in arc length, (n, 3), m."""
        return _in_world(a, self.horizontal, *self.solution.shape(n))

    def lowest_point(self, a: np.ndarray) -> np.ndarray:
        """The lowest point of the tether, (3,), m."""
        return a + float(self.solution.lowest_r) * self.horizontal + np.array([0.0, 0.0, float(self.solution.lowest_z)])


def _mean_tension(dr: float, dz: float, length: float, mu: float, g: float) -> float:
    t_b = catenary.tension_b_point(dr, dz, length, mu, g)
    return t_b - 0.5 * mu * g * dz


def _geometry(a: np.ndarray, b: np.ndarray) -> tuple[float, float, np.ndarray]:
    d = b - a
    dr = math.hypot(d[0], d[1])
    if dr <= _VERTICAL_DR:
        return 0.0, float(d[2]), np.array([1.0, 0.0, 0.0])
    return dr, float(d[2]), np.array([d[0] / dr, d[1] / dr, 0.0])


def _stretched_length(dr: float, dz: float, length: float, mu: float, ea: float, g: float) -> float:
    """L_s with L_s = L (1 + T_mean(L_s) / EA), bracketed from the chord up."""
    chord = math.hypot(dr, dz)

    def excess(ls: float) -> float:
        return ls - length * (1.0 + _mean_tension(dr, dz, ls, mu * length / ls, g) / ea)

    lo = max(length, chord * (1.0 + _TAUT_MARGIN))
    if excess(lo) >= 0.0:
        ls = lo
    else:
        step = max(lo * 1e-6, 1e-9)
        hi = lo + step
        while excess(hi) < 0.0:
            step *= 4.0
            hi = lo + step
        ls = brentq(excess, lo, hi, xtol=1e-12 * max(1.0, lo), rtol=1e-15)
    return ls


def solve(a: np.ndarray, b: np.ndarray, length: float, mu: float, ea: float, g: float) -> ElasticCatenary:
    """Elastic catenary of unstretched length ``length`` from point a to point b (world, z up)."""
    dr, dz, horizontal = _geometry(a, b)
    ls = _stretched_length(dr, dz, length, mu, ea, g)
    return ElasticCatenary(catenary.solve(dr, dz, ls, mu * length / ls, g), ls, horizontal)


def shape_points(a: np.ndarray, b: np.ndarray, length: float, mu: float, ea: float, g: float,
                 n: int) -> np.ndarray:
    """``solve(a, b, length, mu, ea, g).points(a, n)`` on scalar paths (:func:`catenary.shape_point`),
    for one catenary at a time (the markers' reference shape): 79 µs against 452 µs here. The
    points agree to 3e-10 of the length for ends 1 m or more apart horizontally and to 3e-8 at
    0.1 m; within millimetres of a vertical hang the closed form's sensitivity to the rounding
    of u shows (5e-5 at 0.2 mm).
    """
    dr, dz, horizontal = _geometry(a, b)
    return _in_world(a, horizontal, *catenary.shape_point(dr, dz, _stretched_length(dr, dz, length, mu, ea, g), n))


def _in_world(a: np.ndarray, horizontal: np.ndarray, r: np.ndarray, z: np.ndarray) -> np.ndarray:
    return a[None, :] + r[:, None] * horizontal[None, :] + z[:, None] * np.array([0.0, 0.0, 1.0])


def end_tensions(a: np.ndarray, b: np.ndarray, length: float, mu: float, ea: float,
                 g: float) -> tuple[float, float, np.ndarray]:
    """Tensions at A and B (N) and the unit tangent at B (away from A): what the winch and
    the UAV body need each internal step, on scalar ``math`` paths (about 100 times faster
    than :func:`solve`; equal to it to rounding).
    """
    dr, dz, horizontal = _geometry(a, b)
    ls = _stretched_length(dr, dz, length, mu, ea, g)
    mu_s = mu * length / ls
    clamped, s, u = catenary.point_parameters(dr, dz, ls)
    t_b = catenary.tension_b_from_parameters(dr, dz, clamped, s, u, mu_s * g)
    t_a = t_b - mu_s * g * dz
    if dr == 0.0:
        sin_b = 1.0 if dz + ls > 0.0 and ls != -dz else -1.0
        return t_a, t_b, np.array([0.0, 0.0, sin_b])
    beta = math.atan(math.sinh(math.atanh(dz / ls) + u))
    return t_a, t_b, math.cos(beta) * horizontal + np.array([0.0, 0.0, math.sin(beta)])


def _hanging(dr: float, dz: float, chord: float, u: float) -> tuple[float, float, float, float, float]:
    """The catenary through (dr > 0, dz) of parameter u = dr/(2a), Sec. 3.1.1: its length L_s,
    the slack L_s - chord, tau = T_B/(mu_s g) (Eq. 3.12, a length), dtau/dL_s and dL_s/du.

    Eq. 3.4 as S = sqrt(L_s^2 - dz^2) = dr sinh(u)/u gives dS/du = S (coth u - 1/u), so
    dL_s/du = S^2 (coth u - 1/u)/L_s; with m = artanh(dz/L_s), dm/dL_s = -dz/S^2, and
    tau = dr cosh(m + u)/(2u) gives dln(tau) = (tanh(m + u) - 1/u) du + tanh(m + u) dm.
    """
    x = catenary.sinhc_minus_one_point(u)
    s = dr * (1.0 + x)
    excess = x * dr * (s + dr)  # L_s^2 - chord^2
    ls = math.sqrt(chord * chord + excess)
    m = math.copysign(math.log((ls + abs(dz)) / s), dz)  # artanh(dz/L_s) = sign(dz) ln((L_s + |dz|)/S)
    tau = 0.5 * s * (math.exp(m) + math.exp(-m - 2.0 * u)) / -math.expm1(-2.0 * u)
    # coth u - 1/u = (cosh u - 1 - x)/sinh u, where the two 1/u would cancel for small u
    coth_minus = (2.0 * math.sinh(0.5 * u) ** 2 - x) / math.sinh(u) if u < 1.0 else 1.0 / math.tanh(u) - 1.0 / u
    dls_du = s * s * coth_minus / ls
    t = math.tanh(m + u)
    dtau = tau * ((t - 1.0 / u) / dls_du - t * dz / (s * s))
    return ls, excess / (ls + chord), tau, dtau, dls_du


def _hanging_root(dr: float, dz: float, length: float, line_weight: float,
                  ea: float) -> tuple[float, float, float] | None:
    """(L_s, tau, dtau/dL_s) at the root of F = L_s - L (1 + T_mean/EA) for dr > 0, or None
    where Newton's method does not reach it beyond the bound :func:`_stretched_length` keeps.

    Newton's method in u = dr/(2a), each step taken in 1/u (where a nearly taut tether's
    tension is linear) and at most doubling u, with F_Ls = 1 - (L/EA)(W tau' - T_mean)/L_s.
    It starts from the slack L - chord plus the stretch of a vertical hang, L W/(2 EA), plus
    chord (dr mu g/EA)^(2/3)/24^(1/3), where the stretch L T/EA of a nearly taut catenary
    equals its slack L_s - chord = dr^2 (mu g)^2 chord/(24 T^2).
    """
    weight = line_weight * length
    chord = math.hypot(dr, dz)
    slack = (max(length - chord, 0.0) + 0.5 * length * weight / ea
             + chord * (dr * line_weight / ea) ** (2.0 / 3.0) / 24.0 ** (1.0 / 3.0))
    excess = slack * (2.0 * chord + slack)
    s = math.sqrt(dr * dr + excess)
    u = catenary.inverse_sinhc_point(excess / ((s + dr) * dr))
    for _ in range(_MAX_NEWTON):
        if not 0.0 < u < _MAX_U:
            return None
        ls, slack, tau, dtau, dls_du = _hanging(dr, dz, chord, u)
        t_mean = weight * (tau - 0.5 * dz) / ls
        f = ls - length * (1.0 + t_mean / ea)
        f_ls = 1.0 - length / ea * (weight * dtau - t_mean) / ls
        if f_ls <= 0.0 or slack <= _TAUT_MARGIN * chord:
            return None
        if abs(f) <= _ROOT_TOLERANCE * length * f_ls:
            return (ls, tau, dtau) if ls > length else None
        u /= max(1.0 + f / (f_ls * dls_du * u), 0.5)
    return None


def _implicit_slope(length: float, dz: float, ls: float, tau: float, dtau: float, weight: float, ea: float) -> float:
    """dT_A/dL (N/m) at the root L_s of F = L_s - L (1 + T_mean/EA), from tau(L_s) and dtau/dL_s.

    With W = mu g L, T_A = W (tau - dz)/L_s and T_mean = W (tau - dz/2)/L_s:
    dT_A/dL = T_A/L + (W tau' - T_A)/L_s dL_s/dL, and dL_s/dL = -F_L/F_Ls
    = (1 + 2 T_mean/EA) / (1 - (L/EA)(W tau' - T_mean)/L_s).
    """
    t_a = weight * (tau - dz) / ls
    t_mean = weight * (tau - 0.5 * dz) / ls
    dls_dl = (1.0 + 2.0 * t_mean / ea) / (1.0 - length / ea * (weight * dtau - t_mean) / ls)
    return t_a / length + (weight * dtau - t_a) / ls * dls_dl


def tension_a_slope(dr: float, dz: float, length: float, mu: float, ea: float, g: float) -> float:
    """dT_A/dL (N/m): the slope in the unstretched length of the guide-way tension of
    :func:`end_tensions`, for the end at horizontal distance ``dr`` >= 0 and height ``dz`` (m).

    The catenary of Thesis Sec. 3.1.1 (Eq. 3.4, 3.12) scales with the line density, so
    T_B = mu_s g tau(L_s) with mu_s = mu L/L_s, and the stretch condition
    F = L_s - L (1 + T_mean/EA) = 0 is differentiated implicitly (:func:`_implicit_slope`)
    at its root (:func:`_hanging_root`). A vertical hang has tau = (L_s + dz)/2, tau' = 1/2
    and T_mean = W/2, so L_s = L (1 + W/(2 EA)). Where the root lies on the bound that
    :func:`_stretched_length` keeps (a taut vertical hang) or Newton's method fails, the
    slope is the central difference of the tension over +-1e-4 L.
    """
    if dr <= _VERTICAL_DR:
        dr = 0.0
        weight = mu * g * length
        ls = length * (1.0 + 0.5 * weight / ea)
        root = (ls, 0.5 * (ls + dz), 0.5) if ls > max(length, abs(dz) * (1.0 + _TAUT_MARGIN)) else None
    else:
        root = _hanging_root(dr, dz, length, mu * g, ea)
    if root is not None:
        return _implicit_slope(length, dz, *root, mu * g * length, ea)
    h = _SLOPE_STEP * length
    a, b = np.zeros(3), np.array([dr, 0.0, dz])
    return (end_tensions(a, b, length + h, mu, ea, g)[0] - end_tensions(a, b, length - h, mu, ea, g)[0]) / (2.0 * h)
