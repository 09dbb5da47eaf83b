"""Reference tether length for the reel controller, thesis Sec. 4.3 (Eq. 4.4, 4.5).

The controller (Sec. 4.2, 50 Hz) needs the heave-robust length L_rob5 for the current
radial distance ``Δr`` and height ``Δz`` of the UAV over the reel. The thesis uses

* Eq. 4.4, the 3rd-order fit of Table 3.2 (row L_rob5), for ``Δr/Δz ≤ 1.1``;
* Eq. 4.5, a 2nd-order extension, for ``Δr/Δz ≥ 1.3``;
* a linear blend of the two in between.

The thesis states the blend range twice, as 1.1-1.3 and as 1.2-1.3. This module blends
over **1.1-1.3**: it is the only reading that assigns a model to every ratio (with 1.2-1.3
the band 1.1-1.2 would belong to neither rule), and its wider band halves the extra slope
the blend adds (the two fits differ by 0.6 % of L at 1.1 and 0.8 % at 1.3).

Against the exact L_rob5 over Δz 2-60 m, Δr/Δz 0-2 (``tethersim catenary reference``):
Eq. 4.4 is within 0.16 % of L, the blend 0.30 %, Eq. 4.5 0.37 %; beyond Δr/Δz ≈ 1.34
Eq. 4.5 exceeds the slack length and is clamped to it (0.39 % above exact).

Outside the fitted region the polynomials are nonsense (Eq. 4.4 has an inflection at
1.22 and reaches -100 km for Δr ≫ Δz; Eq. 4.5 grows like Δr²/Δz). This model never
returns them there:

* ``Δz ≤ 0`` (UAV level with or below the reel): no catenary stays above the reel, the
  heave-robust length does not exist; the chord (taut) length is returned, ``'clamped'``.
  It is the limit of the exact L_rob as ``Δz → 0⁺``.
* ``Δr/Δz > RATIO_MAX``: the exact shooting-method solve is used, ``'exact'``.
* inside, any polynomial value outside ``[chord, L_slack]`` (too short to exist, or so
  long that the tether leaves the reel downwards, α < 0) is clamped to it, ``'clamped'``.

``mode='exact'`` always solves the heave-robust length (about 0.1 ms per point).

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 4.3, Eq. 4.4-4.5, Fig. 4.3; Table 3.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tether_dynamics.statics import heave_robustness

POLY3 = (0.9964, 0.1514, 0.4674, -0.1280)
"""Eq. 4.4 coefficients c1..c4 (Table 3.2, row L_rob5)."""

POLY2 = (0.9748, 0.2615, 0.2370)
"""Eq. 4.5 coefficients d1..d3."""

BLEND = (1.1, 1.3)
"""Δr/Δz band of the linear blend between Eq. 4.4 and Eq. 4.5 (see module docstring)."""

RATIO_MAX = 2.0
"""Largest Δr/Δz at which the polynomial models are used; beyond it, the exact solve."""

RISE = 0.05
"""Tension rise defining the reference length (L_rob5, the row Eq. 4.4 repeats)."""

MODELS = ('poly3', 'poly2', 'blend', 'exact', 'clamped')


@dataclass(frozen=True)
class ReferenceLength:
    """A reference length (m) and the name of the model that produced it."""

    length: float
    model: str


def _poly(coefficients: tuple[float, ...], ratio: float) -> float:
    return sum(c * ratio**i for i, c in enumerate(coefficients))


def reference_length(dr: float, dz: float, mode: str = 'poly') -> ReferenceLength:
    """Return the reference length for radial distance ``dr`` and height ``dz`` (m).

    ``mode='poly'`` evaluates Eq. 4.4 / 4.5 / blend with the safeguards above;
    ``mode='exact'`` solves L_rob5 by the shooting method (Sec. 3.1.2).
    """
    if mode not in ('poly', 'exact'):
        msg = f"mode must be 'poly' or 'exact' (got {mode!r})"
        raise ValueError(msg)
    if not (math.isfinite(dr) and math.isfinite(dz)) or dr < 0.0:
        msg = f'reference length needs finite dr >= 0 and dz (got {dr}, {dz})'
        raise ValueError(msg)
    chord = math.hypot(dr, dz)
    if dz <= 0.0:
        return ReferenceLength(chord, 'clamped')
    ratio = dr / dz
    if mode == 'exact' or ratio > RATIO_MAX:
        return ReferenceLength(heave_robustness.robust_length_point(dr, dz, RISE)[0], 'exact')
    lo, hi = BLEND
    if ratio <= lo:
        model, scaled = 'poly3', _poly(POLY3, ratio)  # Eq. 4.4
    elif ratio >= hi:
        model, scaled = 'poly2', _poly(POLY2, ratio)  # Eq. 4.5
    else:
        weight = (ratio - lo) / (hi - lo)
        model = 'blend'
        scaled = (1.0 - weight) * _poly(POLY3, ratio) + weight * _poly(POLY2, ratio)
    length = dz * scaled
    slack = heave_robustness.slack_length_point(dr, dz)
    if not chord <= length <= slack:
        return ReferenceLength(min(max(length, chord), slack), 'clamped')
    return ReferenceLength(length, model)


def reference_lengths(dr: np.ndarray, dz: np.ndarray,
                      mode: str = 'poly') -> tuple[np.ndarray, np.ndarray]:
    """Vectorized :func:`reference_length`: arrays of lengths (m) and model names."""
    dr, dz = np.broadcast_arrays(np.asarray(dr, dtype=float), np.asarray(dz, dtype=float))
    if mode not in ('poly', 'exact'):
        msg = f"mode must be 'poly' or 'exact' (got {mode!r})"
        raise ValueError(msg)
    if np.any(~np.isfinite(dr) | ~np.isfinite(dz)) or np.any(dr < 0.0):
        msg = 'reference lengths need finite dr >= 0 and dz'
        raise ValueError(msg)
    chord = np.hypot(dr, dz)
    above = dz > 0.0
    dzs = np.where(above, dz, 1.0)
    ratio = dr / dzs
    exact_lanes = above & ((ratio > RATIO_MAX) | (mode == 'exact'))
    l_exact = np.zeros_like(chord)
    if np.any(exact_lanes):
        l_exact[exact_lanes] = heave_robustness.robust_length(
            dr[exact_lanes], dz[exact_lanes], RISE).length
    lo, hi = BLEND
    poly3 = dzs * np.polynomial.polynomial.polyval(ratio, POLY3)
    poly2 = dzs * np.polynomial.polynomial.polyval(ratio, POLY2)
    weight = np.clip((ratio - lo) / (hi - lo), 0.0, 1.0)
    poly = (1.0 - weight) * poly3 + weight * poly2
    slack = heave_robustness.slack_length(np.where(above, dr, 0.0), dzs)
    clamp = ~((chord <= poly) & (poly <= slack))
    names = np.where(ratio <= lo, 'poly3', np.where(ratio >= hi, 'poly2', 'blend'))
    names = np.where(clamp, 'clamped', names)
    length = np.clip(poly, chord, slack)
    length = np.where(exact_lanes, l_exact, length)
    names = np.where(exact_lanes, 'exact', names)
    length = np.where(above, length, chord)
    names = np.where(above, names, 'clamped')
    return length, names.astype(object)
