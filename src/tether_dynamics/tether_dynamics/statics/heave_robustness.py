"""Heave robustness of a hanging tether, thesis Sec. 3.1.2 (Eq. 3.13-3.15).

With the tether length held fixed, the boat (reel, point A) may heave:

* **up** until the tether goes slack, i.e. the departure angle at the reel reaches
  ``α = 0`` and the vertex of the catenary sits at A. With ``v = Δr/a₁`` Eq. 3.13 reads
  ``sinh(v)/v = L/Δr`` and Eq. 3.14 becomes ``Δy₁ = Δz - L tanh(v/2)``;
* **down** until the tension at the UAV reaches ``T_rob = (1 + rise) T_slack``, where
  ``T_slack`` is the UAV tension at the slack length of the nominal position.

The heave-robust length ``L_rob`` gives equal tolerance both ways, ``Δy₁ = Δy₂``: the
shooting method of Sec. 3.1.2. Here it is a root find along the one-parameter family of
"slack after heaving up by Δy₁" shapes, parametrized by ``v ∈ (0, v_slack]``: every ``v``
gives ``L`` and ``Δy₁`` in closed form, and one catenary solve (Eq. 3.4, 3.12) at the
position lowered by ``Δy₂ = Δy₁`` gives the tension to compare with ``T_rob``.

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 3.1.2, Fig. 3.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from tether_dynamics.statics import catenary
from tether_models.constants import GRAVITY

_BISECTIONS = 64


def _log_coshc(v: np.ndarray) -> np.ndarray:
    """Return ``ln((cosh v - 1)/v) = ln(2 sinh²(v/2)/v)`` for ``v > 0`` without overflow."""
    half = 0.5 * v
    log_sinh = half + np.log(-np.expm1(-2.0 * half)) - math.log(2.0)
    return math.log(2.0) + 2.0 * log_sinh - np.log(v)


def inverse_coshc(kappa: np.ndarray) -> np.ndarray:
    """Solve ``(cosh v - 1)/v = κ`` for ``v > 0`` (vertex-at-reel shape, Eq. 3.14 at Δy₁ = 0).

    Newton's method in ``w = ln v`` on ``ln((cosh v - 1)/v) - ln κ``, which is convex in
    ``w``; ``κ = inf`` gives ``v = inf``.
    """
    k = np.asarray(kappa, dtype=float)
    if np.any(k <= 0.0):
        msg = 'inverse_coshc needs a positive kappa'
        raise ValueError(msg)
    infinite = np.isinf(k)
    kk = np.where(infinite, 1.0, k)
    target = np.log(kk)
    big = np.log(2.0 * kk + 1.0)
    w = np.log(np.where(kk < 1.0, 2.0 * kk, big + np.log(big)))
    for _ in range(60):
        v = np.exp(w)
        step = (_log_coshc(v) - target) / (v / np.tanh(0.5 * v) - 1.0)
        w = w - step
        if np.all(np.abs(step) <= 1e-9):
            v = np.exp(w)
            w = w - (_log_coshc(v) - target) / (v / np.tanh(0.5 * v) - 1.0)
            break
    else:
        msg = 'inverse_coshc: Newton iteration did not converge'
        raise RuntimeError(msg)
    return np.where(infinite, np.inf, np.exp(w))


def _check_above(dr: np.ndarray, dz: np.ndarray) -> None:
    if np.any(dr < 0.0):
        msg = f'horizontal distance dr must be >= 0 (got min {np.min(dr):.6g} m)'
        raise ValueError(msg)
    if np.any(dz <= 0.0):
        msg = (f'heave robustness needs the UAV above the reel (dz > 0, got min '
               f'{np.min(dz):.6g} m): level or lower, every catenary sags below the reel')
        raise ValueError(msg)


def slack_parameter(dr: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """Return ``v_s = Δr/a`` of the slack shape (vertex at the reel, α = 0) through (Δr, Δz)."""
    dr, dz = np.broadcast_arrays(np.asarray(dr, dtype=float), np.asarray(dz, dtype=float))
    _check_above(dr, dz)
    with np.errstate(divide='ignore'):
        return inverse_coshc(dz / dr)


def slack_length(dr: np.ndarray, dz: np.ndarray) -> np.ndarray:
    """Return the slack length ``L_slack`` (m): the longest length with ``α ≥ 0``.

    From Eq. 3.13-3.14 at ``Δy₁ = 0``: ``L_slack = Δz / tanh(v_s/2)``.
    """
    dz = np.asarray(dz, dtype=float)
    return dz / np.tanh(0.5 * slack_parameter(dr, dz))


def slack_tension(dr: np.ndarray, dz: np.ndarray,
                  linear_density: float = catenary.THESIS_LINEAR_DENSITY,
                  gravity: float = GRAVITY) -> np.ndarray:
    """Return the UAV tension at the slack length (N), Eq. 3.12 with α = 0.

    ``T_slack = λ g a cosh(v_s) = λ g L_slack / tanh(v_s)``.
    """
    dz = np.asarray(dz, dtype=float)
    v = slack_parameter(dr, dz)
    return linear_density * gravity * dz / (np.tanh(0.5 * v) * np.tanh(v))


def upward_heave_limit(dr: np.ndarray, dz: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Return ``Δy₁`` (m), how far the reel may rise before the tether goes slack.

    Eq. 3.13 ``L = a₁ sinh(Δr/a₁)`` solved for ``v = Δr/a₁``, then Eq. 3.14,
    ``Δy₁ = Δz - a₁ (cosh v - 1) = Δz - L tanh(v/2)``. Negative when ``L > L_slack``.
    """
    dr, dz, length = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (dr, dz, length)))
    if np.any(length < dr):
        msg = 'tether length shorter than the horizontal distance: no slack shape exists'
        raise ValueError(msg)
    with np.errstate(divide='ignore', invalid='ignore'):
        v = catenary.inverse_sinhc(np.where(dr == 0.0, np.inf, (length - dr) / dr))
    return dz - length * np.tanh(0.5 * v)


@dataclass(frozen=True)
class HeaveRobustness:
    """Heave-robust operating point for a tension rise, Sec. 3.1.2 (arrays, batch shape).

    Attributes:
        length: L_rob (m).
        heave: equal up/down heave tolerance Δy₁ = Δy₂ (m).
        slack_length: L_slack (m).  slack_tension : T_slack (N).
        tension_limit: T_rob = (1 + rise) T_slack (N).
        nominal: the catenary at the nominal position with length L_rob.
    """

    length: np.ndarray
    heave: np.ndarray
    slack_length: np.ndarray
    slack_tension: np.ndarray
    tension_limit: np.ndarray
    nominal: catenary.CatenarySolution


def _family(dr: np.ndarray, dz: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(L, Δy₁)`` of the shape that is slack after rising Δy₁, at parameter v."""
    with np.errstate(invalid='ignore'):
        length = dr * (1.0 + catenary.sinhc_minus_one(v))  # Eq. 3.13
    return length, dz - length * np.tanh(0.5 * v)  # Eq. 3.14


def robust_length(dr: np.ndarray | float, dz: np.ndarray | float, rise: float = 0.05,
                  linear_density: float = catenary.THESIS_LINEAR_DENSITY,
                  gravity: float = GRAVITY) -> HeaveRobustness:
    """Solve the heave-robust length L_rob by the shooting method of Sec. 3.1.2 (vectorized).

    Bisection on ``v/v_slack ∈ (0, 1]``: shorter tethers (smaller ``v``) tolerate more
    upward heave and reach the tension limit after less downward heave; at the root the
    tension at the position lowered by ``Δy₂ = Δy₁`` equals ``T_rob`` (Eq. 3.15, 3.12).
    A vertical tether (``Δr = 0``) has ``L_rob = L_slack = Δz`` and no tolerance.
    """
    if rise <= 0.0:
        msg = f'tension rise must be > 0 (got {rise})'
        raise ValueError(msg)
    dr, dz = np.broadcast_arrays(np.asarray(dr, dtype=float), np.asarray(dz, dtype=float))
    v_slack = slack_parameter(dr, dz)
    l_slack = dz / np.tanh(0.5 * v_slack)
    t_slack = slack_tension(dr, dz, linear_density, gravity)
    t_rob = (1.0 + rise) * t_slack
    vertical = dr == 0.0
    vs = np.where(vertical, 1.0, v_slack)
    drs = np.where(vertical, 1.0, dr)
    dzs = np.where(vertical, 1.0, dz)
    lo = np.zeros_like(vs)
    hi = np.ones_like(vs)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        length, heave = _family(drs, dzs, mid * vs)
        too_tight = _too_tight(drs, dzs + heave, length, t_rob,
                               linear_density, gravity)
        lo = np.where(too_tight, mid, lo)
        hi = np.where(too_tight, hi, mid)
    length, heave = _family(drs, dzs, hi * vs)
    length = np.where(vertical, dz, length)
    heave = np.where(vertical, 0.0, heave)
    return HeaveRobustness(length=length, heave=heave, slack_length=l_slack,
                           slack_tension=t_slack, tension_limit=t_rob,
                           nominal=catenary.solve(dr, dz, np.maximum(length, np.hypot(dr, dz)),
                                                  linear_density, gravity))


def _too_tight(dr: np.ndarray, dz_low: np.ndarray, length: np.ndarray, t_rob: np.ndarray,
               linear_density: float, gravity: float) -> np.ndarray:
    """Return True where the lowered position is unreachable or its UAV tension ≥ T_rob."""
    reachable = length > np.hypot(dr, dz_low)
    safe = np.where(reachable, length, np.hypot(dr, dz_low) * 2.0)
    tension = catenary.solve(dr, dz_low, safe, linear_density, gravity).tension_b
    return ~reachable | (tension >= t_rob)


def robust_length_point(dr: float, dz: float, rise: float = 0.05,
                        linear_density: float = catenary.THESIS_LINEAR_DENSITY,
                        gravity: float = GRAVITY) -> tuple[float, float]:
    """Scalar L_rob and heave tolerance (m, m) for controller-rate use, Sec. 3.1.2.

    The same root as :func:`robust_length`, found by Brent's method on
    ``ln(T_B/T_rob)`` along the slack-after-heave family, with ``math``-only catenary
    solves (:func:`catenary.tension_b_point`). The bracket's lower end is where the lowered
    position first becomes reachable (taut, infinite tension), found by Brent's method too.
    """
    if dr < 0.0 or dz <= 0.0 or rise <= 0.0:
        msg = f'robust_length_point needs dr >= 0, dz > 0, rise > 0 (got {dr}, {dz}, {rise})'
        raise ValueError(msg)
    if dr == 0.0:
        return dz, 0.0
    v_slack = float(inverse_coshc(np.asarray(dz / dr)))
    lg = linear_density * gravity
    t_rob = (1.0 + rise) * lg * dz / (math.tanh(0.5 * v_slack) * math.tanh(v_slack))

    def family(v: float) -> tuple[float, float]:
        length = dr * (1.0 + catenary.sinhc_minus_one_point(v))  # Eq. 3.13
        return length, dz - length * math.tanh(0.5 * v)  # Eq. 3.14

    def reach(v: float) -> float:
        length, heave = family(v)
        return length - math.hypot(dr, dz + heave)

    def excess_tension(v: float) -> float:
        length, heave = family(v)
        chord = math.hypot(dr, dz + heave)
        tension = catenary.tension_b_point(dr, dz + heave, max(length, chord),
                                           linear_density, gravity)
        return math.log(tension / t_rob) if math.isfinite(tension) else 800.0

    if reach(v_slack) <= 0.0 or excess_tension(v_slack) >= 0.0:
        # Slack length within rounding of the chord (a vertical tether, or one so flat, dz/dr
        # about 1e-7, that its catenary tension has lost its digits): no tolerance.
        return max(family(v_slack)[0], math.hypot(dr, dz)), 0.0
    v_reach = brentq(reach, 1e-12 * v_slack, v_slack, xtol=1e-15 * v_slack, rtol=1e-15)
    v_rob = brentq(excess_tension, v_reach, v_slack, xtol=1e-14 * v_slack, rtol=1e-15)
    length, heave = family(v_rob)
    return length, heave


def slack_length_point(dr: float, dz: float) -> float:
    """Scalar :func:`slack_length` (m) for controller-rate use (``math`` only)."""
    if dr < 0.0 or dz <= 0.0:
        msg = f'slack length needs dr >= 0 and dz > 0 (got {dr}, {dz})'
        raise ValueError(msg)
    if dr == 0.0:
        return dz
    kappa = dz / dr
    target = math.log(kappa)
    big = math.log(2.0 * kappa + 1.0)
    w = math.log(2.0 * kappa if kappa < 1.0 else big + math.log(big))

    def step(w: float) -> float:
        v = math.exp(w)
        half = 0.5 * v
        log_coshc = (math.log(2.0) + 2.0 * (half + math.log(-math.expm1(-v)) - math.log(2.0))
                     - w)
        return (log_coshc - target) / (v / math.tanh(half) - 1.0)

    for _ in range(60):
        delta = step(w)
        w -= delta
        if abs(delta) <= 1e-9:
            w -= step(w)
            return dz / math.tanh(0.5 * math.exp(w))
    msg = 'slack_length_point: Newton iteration did not converge'
    raise RuntimeError(msg)
