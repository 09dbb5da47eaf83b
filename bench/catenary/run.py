"""Benchmark: catenary solve and reference length for the thesis's 14,400 (Δr, Δz) pairs.

Run: ``cd /work/main && ./tethersim-env python bench/catenary/run.py [--repeats N]``

Two batches, each checked for agreement before it is timed:

A. Catenary parameter of Eq. 3.4 (and the UAV tension) at L = 1.1 × chord:
   the project's vectorized Newton solve, a scipy ``brentq`` loop, and ``pycatenary``
   (the peer; timed on a seeded subset and extrapolated, as stated in the table).
B. Reference length L_rob5 (Sec. 3.3.4, Sec. 4.3) at the pairs shifted by half a grid step:
   the polynomial Eq. 4.4, a lookup table of exact L_rob5 on the 0.5 m grid with bilinear
   interpolation (the thesis: polynomial 2300× faster than its lookup), the same table
   searched for the nearest entry per query, the project's safeguarded model, and the
   exact vectorized and scalar shooting-method solves.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable

import numpy as np
from pycatenary import MooringLine
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq

from tether_dynamics.statics import catenary, flying_space, heave_robustness, reference_length
from tether_models.constants import GRAVITY

LAMBDA = catenary.THESIS_LINEAR_DENSITY
PEER_SUBSET = 400
SCALAR_SUBSET = 400


def best_time(call: Callable[[], object], repeats: int) -> float:
    """Return the best wall time (s) of ``repeats`` calls."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def brentq_loop(dr: np.ndarray, dz: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Catenary parameter a of Eq. 3.4 per pair by Brent's method on an analytic bracket."""
    out = np.empty_like(dr)
    for i, (x, y, ell) in enumerate(zip(dr, dz, length, strict=True)):
        s = np.sqrt(ell * ell - y * y)
        # sinh(t)/t = s/x with t = x/(2a): t in (0, asinh-type upper bound]
        ratio = s / x
        out[i] = x / (2.0 * brentq(lambda t, r=ratio: np.sinh(t) / t - r, 1e-12,
                                   np.log(2.0 * ratio) + 2.0 + np.log(np.log(2.0 * ratio) + 2.0),
                                   xtol=1e-15, rtol=1e-15))
    return out


def pycatenary_loop(dr: np.ndarray, dz: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Catenary parameter a per pair from pycatenary's rigid, floorless line."""
    out = np.empty_like(dr)
    for i, (x, y, ell) in enumerate(zip(dr, dz, length, strict=True)):
        line = MooringLine(fairlead=[x, y], anchor=[0.0, 0.0], L=ell, w=LAMBDA * GRAVITY,
                           floor=False)
        line.compute_solution()
        out[i] = line.catenary.a
    return out


def main() -> int:
    parser = argparse.ArgumentParser(prog='bench/catenary/run.py',
                                     description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=7, help='repeats of the fast methods')
    args = parser.parse_args()
    rng = np.random.default_rng(2021)
    dr, dz = flying_space.grid(0.5)
    length = 1.1 * np.hypot(dr, dz)
    n = dr.size
    subset = np.sort(rng.choice(n, PEER_SUBSET, replace=False))
    print(f'{n} pairs; checking agreement ...', file=sys.stderr)

    # --- A: correctness, then timing -------------------------------------------------------
    a_project = catenary.solve(dr, dz, length).a
    a_brentq = brentq_loop(dr, dz, length)
    a_peer = pycatenary_loop(dr[subset], dz[subset], length[subset])
    dev_brentq = np.max(np.abs(a_brentq / a_project - 1.0))
    dev_peer = np.max(np.abs(a_peer / a_project[subset] - 1.0))
    residual = np.max(catenary.solve(dr, dz, length).residual())
    rows_a = [
        ('project vectorized Newton (numpy)', best_time(lambda: catenary.solve(dr, dz, length),
                                                        args.repeats), n, 'measured'),
        ('project scalar path, Python loop', best_time(lambda: [catenary.tension_b_point(
            x, y, ell) for x, y, ell in zip(dr, dz, length, strict=True)], 3), n, 'measured'),
        ('scipy brentq loop', best_time(lambda: brentq_loop(dr, dz, length), 2), n, 'measured'),
        ('pycatenary 1.0 (peer)', best_time(lambda: pycatenary_loop(
            dr[subset], dz[subset], length[subset]), 2) * n / subset.size, n,
         f'extrapolated from {subset.size} pairs'),
    ]

    # --- B: reference length ---------------------------------------------------------------
    axis = 0.5 * np.arange(1, 121)
    print('building the lookup table of exact L_rob5 ...', file=sys.stderr)
    gx, gy = np.meshgrid(axis, axis, indexing='ij')
    table = heave_robustness.robust_length(gx.ravel(), gy.ravel(), 0.05).length.reshape(gx.shape)
    lookup = RegularGridInterpolator((axis, axis), table)
    qx = np.clip(dr + 0.25, axis[0], axis[-1])
    qy = np.clip(dz + 0.25, axis[0], axis[-1])
    query = np.column_stack([qx, qy])
    c1, c2, c3, c4 = reference_length.POLY3

    def poly() -> np.ndarray:
        return c1 * qy + c2 * qx + c3 * qx * qx / qy + c4 * qx**3 / qy**2  # Eq. 4.4

    exact = heave_robustness.robust_length(qx, qy, 0.05).length
    fitted = (qx / qy) <= 1.1
    dev_poly = np.max(np.abs(poly()[fitted] / exact[fitted] - 1.0))
    lookup_error = np.abs(lookup(query) / exact - 1.0)
    dev_lookup = np.max(lookup_error)
    worst = int(np.argmax(lookup_error))
    model, _ = reference_length.reference_lengths(qx, qy)
    dev_model = np.max(np.abs(model / exact - 1.0))
    scalar_idx = subset[:SCALAR_SUBSET]
    flat_x, flat_y, flat_table = gx.ravel(), gy.ravel(), table.ravel()
    rows_b = [
        ('polynomial Eq. 4.4 (numpy)', best_time(poly, args.repeats * 10), n, 'measured'),
        ('lookup table + bilinear interpolation (scipy)', best_time(lambda: lookup(query),
                                                                    args.repeats), n, 'measured'),
        ('project reference model, vectorized', best_time(
            lambda: reference_length.reference_lengths(qx, qy), args.repeats), n, 'measured'),
        ('exact L_rob5, vectorized shooting', best_time(
            lambda: heave_robustness.robust_length(qx, qy, 0.05), 2), n, 'measured'),
        ('exact L_rob5, scalar (controller path) loop', best_time(lambda: [
            heave_robustness.robust_length_point(qx[i], qy[i]) for i in scalar_idx], 2)
         * n / scalar_idx.size, n, f'extrapolated from {scalar_idx.size} pairs'),
        ('polynomial Eq. 4.4, scalar loop', best_time(lambda: [
            c1 * y + c2 * x + c3 * x * x / y + c4 * x**3 / y**2
            for x, y in zip(qx.tolist(), qy.tolist(), strict=True)], args.repeats), n, 'measured'),
        ('lookup by nearest-entry search, scalar loop', best_time(lambda: [
            flat_table[np.argmin((flat_x - qx[i]) ** 2 + (flat_y - qy[i]) ** 2)]
            for i in scalar_idx], 2) * n / scalar_idx.size, n,
         f'extrapolated from {scalar_idx.size} pairs'),
    ]

    lines = [
        'Agreement (checked before timing):',
        f'  A: max relative residual of Eq. 3.4 (project) {residual:.1e}; a vs brentq '
        f'{dev_brentq:.1e}; a vs pycatenary {dev_peer:.1e} ({subset.size} pairs)',
        f'  B: vs exact L_rob5: Eq. 4.4 (Δr/Δz <= 1.1) {100 * dev_poly:.3f} %, lookup '
        f'{100 * dev_lookup:.3f} % (worst at Δr = {qx[worst]:g} m, Δz = {qy[worst]:g} m; '
        f'median {100 * np.median(lookup_error):.4f} %), project model (all pairs) '
        f'{100 * dev_model:.3f} %',
        '',
    ]
    for title, rows, base in (('A. catenary solve, L = 1.1 chord', rows_a, rows_a[0][1]),
                              ('B. reference length L_rob5', rows_b, rows_b[0][1])):
        lines += [f'{title} ({n} pairs)',
                  f'  {"method":48s} {"total":>10s} {"per pair":>10s} {"× first row":>12s}  note']
        for name, total, count, note in rows:
            lines.append(f'  {name:48s} {_fmt(total):>10s} {_fmt(total / count):>10s} '
                         f'{total / base:12.1f}  {note}')
        lines.append('')
    lookup_ratio = rows_b[1][1] / rows_b[0][1]
    search_ratio = rows_b[6][1] / rows_b[5][1]
    lines.append(f'Lookup / polynomial: vectorized {lookup_ratio:.0f}×, scalar nearest-entry '
                 f'search vs scalar polynomial {search_ratio:.0f}× '
                 '(thesis: 2300×, MATLAB, 3.1 GHz, lookup method not described)')
    if dev_brentq > 1e-10 or dev_peer > 1e-6 or dev_lookup > 0.05 or dev_model > 0.01:
        lines.append('WARNING: methods disagree beyond tolerance')
        print('\n'.join(lines))
        return 1
    print('\n'.join(lines))
    return 0


def _fmt(seconds: float) -> str:
    for unit, scale in (('s', 1.0), ('ms', 1e-3), ('µs', 1e-6), ('ns', 1e-9)):
        if seconds >= scale:
            return f'{seconds / scale:.3g} {unit}'
    return f'{seconds / 1e-9:.3g} ns'


if __name__ == '__main__':
    sys.exit(main())
