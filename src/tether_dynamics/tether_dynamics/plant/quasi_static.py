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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from tether_dynamics.statics import catenary


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
        r, z = self.solution.shape(n)
        return a[None, :] + r[:, None] * self.horizontal[None, :] + z[:, None] * np.array([0.0, 0.0, 1.0])

    def lowest_point(self, a: np.ndarray) -> np.ndarray:
        """The lowest point of the tether, (3,), m."""
        return a + float(self.solution.lowest_r) * self.horizontal + np.array([0.0, 0.0, float(self.solution.lowest_z)])


def _mean_tension(dr: float, dz: float, length: float, mu: float, g: float) -> float:
    t_b = catenary.tension_b_point(dr, dz, length, mu, g)
    return t_b - 0.5 * mu * g * dz


def _geometry(a: np.ndarray, b: np.ndarray) -> tuple[float, float, np.ndarray]:
    d = b - a
    dr = math.hypot(d[0], d[1])
    if dr <= 1e-12:
        return 0.0, float(d[2]), np.array([1.0, 0.0, 0.0])
    return dr, float(d[2]), np.array([d[0] / dr, d[1] / dr, 0.0])


def _stretched_length(dr: float, dz: float, length: float, mu: float, ea: float, g: float) -> float:
    """L_s with L_s = L (1 + T_mean(L_s) / EA), bracketed from the chord up."""
    chord = math.hypot(dr, dz)

    def excess(ls: float) -> float:
        return ls - length * (1.0 + _mean_tension(dr, dz, ls, mu * length / ls, g) / ea)

    lo = max(length, chord * (1.0 + 1e-12))
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


def end_tensions(a: np.ndarray, b: np.ndarray, length: float, mu: float, ea: float,
                 g: float) -> tuple[float, float, np.ndarray]:
    """Tensions at A and B (N) and the unit tangent at B (away from A): what the winch and
    the UAV body need each internal step, on scalar ``math`` paths (about 100 times faster
    than :func:`solve`; equal to it to rounding).
    """
    dr, dz, horizontal = _geometry(a, b)
    ls = _stretched_length(dr, dz, length, mu, ea, g)
    mu_s = mu * length / ls
    t_b = catenary.tension_b_point(dr, dz, ls, mu_s, g)
    t_a = t_b - mu_s * g * dz
    if dr == 0.0:
        sin_b = 1.0 if dz + ls > 0.0 and ls != -dz else -1.0
        return t_a, t_b, np.array([0.0, 0.0, sin_b])
    chord = math.hypot(dr, dz)
    s = math.sqrt(dr * dr + (ls - chord) * (ls + chord))
    u = catenary.inverse_sinhc_point((ls - chord) * (ls + chord) / ((s + dr) * dr))
    beta = math.atan(math.sinh(math.atanh(dz / ls) + u))
    return t_a, t_b, math.cos(beta) * horizontal + np.array([0.0, 0.0, math.sin(beta)])
