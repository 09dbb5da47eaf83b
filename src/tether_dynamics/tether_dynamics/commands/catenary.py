"""``tethersim catenary``: flying-space analysis (Sec. 3.2-3.3) and the reference length (4.3).

Subcommands:

* ``analyze``: the brute-force sweep over the (Δx, Δy) grid, the fits of Tables 3.1-3.3
  next to the thesis's, the recommended operating ratio, the Δy = 55 m / Δx = 20 m heave
  tolerance, and PNG plots in the spirit of Fig. 3.3-3.8. ``--quick`` (default, 2.5 m
  grid) or ``--full`` (the thesis's 0.5 m grid, 14,400 pairs × 480 lengths).
* ``reference``: the polynomial reference-length model (Eq. 4.4/4.5 with blend and
  safeguards) against the exact heave-robust length over the operating envelope
  (Δz 2-60 m, Δr/Δz 0-2), with a plot in the spirit of Fig. 4.3.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from tether_common.command_line import Command
from tether_common.command_line import OneLineParser
from tether_common.command_line import UsageError
from tether_common.command_line import analysis
from tether_dynamics.commands import catenary_plots
from tether_dynamics.statics import catenary, flying_space, heave_robustness, reference_length
from tether_models.constants import GRAVITY

PROG = 'tethersim catenary'
QUICK_STEP = 2.5
FULL_STEP = 0.5
THESIS_RECOMMENDED_RATIO = 0.46
"""Sec. 3.3: "the recommended relative offset ... is Δx/Δy ≈ .46"."""
THESIS_HEAVE_55_20 = 0.75
"""Sec. 3.3: at Δy = 55 m, Δx = 20 m "∼ .75 m heave tolerance in each direction" for < 10 % more tension."""
FLAT = 0.01
"""Relative loss of heave tolerance below which a ratio counts as on the flat top of the maximum."""


def _progress(label: str) -> Callable[[int, int], None]:
    start = time.perf_counter()

    def report(done: int, total: int) -> None:
        elapsed = time.perf_counter() - start
        eta = elapsed / done * (total - done) if done else 0.0
        print(f'\r{label}: {done}/{total} pairs ({100 * done / total:5.1f} %), '
              f'{elapsed:5.1f} s elapsed, ~{eta:4.1f} s left', end='', file=sys.stderr, flush=True)
        if done == total:
            print(file=sys.stderr)

    return report


def _fmt(values: np.ndarray) -> str:
    return ' '.join(f'{v:9.4f}' for v in values)


def _table_lines(table: str, fits: dict[str, flying_space.Fit], source: str) -> list[str]:
    title = {'tension': 'Table 3.1, tension T/(λ Δy), Eq. 3.17',
             'length': 'Table 3.2, length L/Δy, Eq. 3.18',
             'angle': 'Table 3.3, departure angle α (deg), Eq. 3.19'}[table] + f' — {source}'
    unit = {'tension': 'N·m/kg', 'length': '(L/Δy)', 'angle': 'deg'}[table]
    lines = [title, f'  {"row":11s} {"source":7s} {"coefficients c1..cn":54s} {"R²":>7s}'
                    f'   max|Δ| over Δx/Δy in [0, 1.2]']
    for name, fit in fits.items():
        thesis = flying_space.thesis_fit(table, name)
        diff, where = flying_space.max_curve_difference(fit, thesis)
        scale = np.max(np.abs(thesis(np.linspace(0.0, 1.2, 241))))
        lines.append(f'  {name:11s} {"project":7s} {_fmt(fit.coefficients):54s} '
                     f'{fit.r_squared:7.5f}   {diff:.4f} {unit} at {where:.2f}'
                     f' ({100 * diff / scale:.2f} % of max |thesis|)')
        lines.append(f'  {"":11s} {"thesis":7s} {_fmt(thesis.coefficients):54s} '
                     f'{thesis.r_squared:7.5f}')
    return lines


def _exact_vs_sweep(result: flying_space.SweepResult) -> list[str]:
    """Discretization error of the 480-length sweep against the root-found values."""
    dx, dy = result.dx, result.dy
    lines = ['Sweep discretization error (swept minus exact, relative to L):']
    l_min = flying_space.min_tension_length(dx, dy)
    l_slack = heave_robustness.slack_length(dx, dy)
    pairs = [('L_min', result.length_min, l_min), ('L_slack', result.length_slack, l_slack)]
    for rise, l_rob in zip(flying_space.RISES, result.rob_length, strict=True):
        exact = heave_robustness.robust_length(dx, dy, rise).length
        pairs.append((f'L_rob{round(100 * rise)}', l_rob, exact))
    for name, swept, exact in pairs:
        rel = (swept - exact) / exact
        lines.append(f'  {name:9s} max |rel| {np.max(np.abs(rel)):.2e}, mean {np.mean(rel):+.2e}')
    return lines


def _exact_vs_thesis_fit() -> list[str]:
    """How far the thesis's length fits are from the exact curves (no sweep, no fit)."""
    x = np.linspace(0.05, 1.2, 231)
    exact = {'L_slack': heave_robustness.slack_length(x, 1.0),
             'L_min': flying_space.min_tension_length(x, np.ones_like(x))}
    for rise in flying_space.RISES:
        exact[f'L_rob{round(100 * rise)}'] = heave_robustness.robust_length(x, 1.0, rise).length
    lines = ['Exact nondimensional lengths vs the thesis fits (Table 3.2), Δx/Δy in [0.05, 1.2]:']
    for name, values in exact.items():
        rel = flying_space.thesis_fit('length', name)(x) / values - 1.0
        i = int(np.argmax(np.abs(rel)))
        lines.append(f'  {name:9s} max |thesis fit / exact - 1| = {100 * abs(rel[i]):.3f} % '
                     f'at Δx/Δy = {x[i]:.2f}')
    return lines


def analyze(args: argparse.Namespace) -> str:
    """Run the flying-space analysis and write plots; return the summary text."""
    step = FULL_STEP if args.full else (args.step or QUICK_STEP)
    out = args.out
    dx, dy = flying_space.grid(step, args.extent)
    print(f'{PROG} analyze: {dx.size} positions × {args.lengths} lengths '
          f'({dx.size * args.lengths / 1e6:.2f} M catenaries, ×2 with the shooting method)',
          file=sys.stderr)
    t0 = time.perf_counter()
    lam, g = catenary.THESIS_LINEAR_DENSITY, GRAVITY
    result = flying_space.sweep(dx, dy, args.lengths, linear_density=lam, gravity=g, progress=_progress('sweep'))
    t_sweep = time.perf_counter() - t0
    fits = flying_space.fit_tables(result, lam)
    print('exact comparisons and plots ...', file=sys.stderr)
    best_ratio, best_heave = flying_space.recommended_ratio(0.05)
    thesis_heave = float(flying_space.heave_tolerance_curve(
        np.array([THESIS_RECOMMENDED_RATIO]), 0.05)[0])
    heave_55 = [float(heave_robustness.robust_length(20.0, 55.0, rise).heave)
                for rise in flying_space.RISES]
    lines = [
        f'Flying-space analysis (thesis Sec. 3.2-3.3): grid step {step:g} m to {args.extent:g} m '
        f'({dx.size} pairs), {args.lengths} lengths per pair, λ = {lam} kg/m, '
        f'g = {g} m/s²',
        f'Sweep time {t_sweep:.1f} s ({dx.size * args.lengths / t_sweep / 1e6:.2f} M lengths/s)',
        f'Fits: least squares over all grid pairs with Δx/Δy <= {flying_space.FIT_RATIO_MAX}, '
        'in the nondimensional variables (Eq. 3.16)',
        '',
    ]
    for table in ('tension', 'length', 'angle'):
        lines += [*_table_lines(table, fits[table], 'fits of the 480-length sweep'), '']
    exact_fits = flying_space.fit_data(dx / dy, flying_space.exact_curve_data(dx, dy, lam, g))
    for table in ('tension', 'length', 'angle'):
        lines += [*_table_lines(table, exact_fits[table], 'fits of root-found exact values'), '']
    lines += _exact_vs_sweep(result) + [''] + _exact_vs_thesis_fit() + ['']
    lines += [_ratio_sentence(best_ratio, best_heave, thesis_heave),
              _heave_sentence(heave_55)]
    plots = [
        catenary_plots.shapes(out / 'fig3_3_shapes.png'),
        catenary_plots.tension_vs_length(out / 'fig3_4_tension_vs_length.png'),
    ]
    if np.any(np.isclose(result.dy, 55.0)):
        plots += [
            catenary_plots.margins(out / 'fig3_5_heave_margins.png', result),
            catenary_plots.fitted_quantity(out / 'fig3_6_tension.png', result, 'tension', fits,
                                           lam),
            catenary_plots.fitted_quantity(out / 'fig3_7_length.png', result, 'length', fits, lam),
            catenary_plots.fitted_quantity(out / 'fig3_8_angle.png', result, 'angle', fits, lam),
        ]
    lines += ['', 'Plots: ' + ', '.join(p.name for p in plots)]
    return '\n'.join(lines)


def _ratio_sentence(best_ratio: float, best_heave: float, thesis_heave: float) -> str:
    """The recommended ratio against the thesis's, and whether the difference costs heave tolerance."""
    loss = 1.0 - thesis_heave / best_heave
    verdict = (f'less than {100 * FLAT:g} %: the maximum is flat, so the two ratios are equally good'
               if loss < FLAT else
               f'at least {100 * FLAT:g} %: the thesis\'s ratio gives up a measurable part of the tolerance')
    return (f'Recommended operating ratio (max heave tolerance, 5 % rise, exact): Δx/Δy = {best_ratio:.3f}, '
            f'tolerance {best_heave:.5f}·Δy; thesis (Sec. 3.3) Δx/Δy ≈ {THESIS_RECOMMENDED_RATIO} '
            f'(difference {best_ratio - THESIS_RECOMMENDED_RATIO:+.3f}), where the tolerance is '
            f'{thesis_heave:.5f}·Δy, {100 * loss:.2f} % less, {verdict}')


def _heave_sentence(heave: list[float]) -> str:
    """Heave tolerance at Δy = 55 m, Δx = 20 m per rise, against the thesis's ~0.75 m for < 10 % rise."""
    by_rise = dict(zip(flying_space.RISES, heave, strict=True))
    below_10 = by_rise[0.10]
    return ('Heave tolerance at Δy = 55 m, Δx = 20 m (each way): '
            + ', '.join(f'{round(100 * r)} % rise {h:.3f} m' for r, h in by_rise.items())
            + f'; thesis (Sec. 3.3) "∼ .75 m" for < 10 % rise: this model gives {below_10:.3f} m at 10 %, '
            f'{below_10 - THESIS_HEAVE_55_20:+.3f} m from it')


def envelope_report(dz_values: np.ndarray, ratios: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Compare the reference model with the exact L_rob5; return text lines and the error map."""
    dz, ratio = np.meshgrid(dz_values, ratios, indexing='ij')
    dr = ratio * dz
    model, names = reference_length.reference_lengths(dr, dz)
    exact = heave_robustness.robust_length(dr, dz, reference_length.RISE).length
    poly3 = dz * np.polynomial.polynomial.polyval(ratio, reference_length.POLY3)
    error = model - exact
    lines = [f'Reference length model vs exact L_rob5 over Δz '
             f'{dz_values[0]:g}-{dz_values[-1]:g} m, '
             f'Δr/Δz {ratios[0]:g}-{ratios[-1]:g} ({dz.size} points):',
             f'  {"model used":10s} {"points":>7s} {"Δr/Δz range":>13s} {"max|Δ| m":>9s} '
             f'{"max|Δ|/L":>9s} {"mean Δ m":>9s}']
    for name in reference_length.MODELS:
        use = names == name
        if not np.any(use):
            continue
        rel = np.abs(error[use]) / exact[use]
        lines.append(f'  {name:10s} {int(np.sum(use)):7d} '
                     f'{ratio[use].min():6.2f}-{ratio[use].max():<6.2f}'
                     f' {np.max(np.abs(error[use])):9.4f} {100 * np.max(rel):8.3f}% '
                     f'{np.mean(error[use]):+9.4f}')
    worst = np.unravel_index(np.argmax(np.abs(error)), error.shape)
    lines.append(f'  overall: max |model - exact| = {np.abs(error[worst]):.4f} m at Δz = '
                 f'{dz[worst]:g} m, Δr/Δz = {ratio[worst]:.2f} ({names[worst]})')
    raw = poly3 - exact
    raw_worst = np.unravel_index(np.argmax(np.abs(raw)), raw.shape)
    far = 0.5 * np.polynomial.polynomial.polyval(120.0, reference_length.POLY3)
    lines.append(f'  unguarded Eq. 4.4 alone: max |poly3 - exact| = '
                 f'{np.abs(raw[raw_worst]):.3f} m at Δz = {dz[raw_worst]:g} m, '
                 f'Δr/Δz = {ratio[raw_worst]:.2f}; at Δr = 60 m, Δz = 0.5 m it gives {far:.0f} m')
    return lines, error


def reference(args: argparse.Namespace) -> str:
    """Compare the reference-length model with the exact solve; return the summary text."""
    out = args.out
    dz_values = np.linspace(2.0, 60.0, 59)
    ratios = np.linspace(0.0, 2.0, 201)
    print(f'{PROG} reference: {dz_values.size * ratios.size} envelope points ...', file=sys.stderr)
    lines, error = envelope_report(dz_values, ratios)
    t_poly = _time_point(lambda: reference_length.reference_length(12.0, 30.0))
    t_exact = _time_point(lambda: reference_length.reference_length(12.0, 30.0, 'exact'))
    lines += [
        f'Blend between Eq. 4.4 and Eq. 4.5 over Δr/Δz {reference_length.BLEND[0]}-'
        f'{reference_length.BLEND[1]}; polynomial models up to Δr/Δz = '
        f'{reference_length.RATIO_MAX}, '
        'exact beyond; Δz <= 0 → chord (clamped)',
        f'Single-point cost: poly {1e6 * t_poly:.1f} µs, exact {1e6 * t_exact:.1f} µs '
        f'({t_exact / t_poly:.0f}x the polynomial)',
    ]
    plots = [catenary_plots.reference_model(out / 'fig4_3_reference_model.png'),
             catenary_plots.reference_error_map(out / 'reference_error_map.png', dz_values,
                                                ratios, error)]
    lines += ['', 'Plots: ' + ', '.join(p.name for p in plots)]
    return '\n'.join(lines)


def _time_point(call: Callable[[], object], repeats: int = 200) -> float:
    best = np.inf
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(repeats):
            call()
        best = min(best, (time.perf_counter() - start) / repeats)
    return best


def _arguments(parser: argparse.ArgumentParser) -> None:
    """Add the subcommands of ``tethersim catenary`` to its parser."""
    sub = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)
    p_an = sub.add_parser('analyze', help='flying-space analysis and fits (Sec. 3.2-3.3)')
    grid = p_an.add_mutually_exclusive_group()
    grid.add_argument('--quick', action='store_true',
                      help=f'coarse {QUICK_STEP} m grid (default)')
    grid.add_argument('--full', action='store_true', help=f'the thesis grid, {FULL_STEP} m')
    grid.add_argument('--step', type=float, help='grid step in m')
    p_an.add_argument('--extent', type=float, default=60.0, help='grid extent in m (60)')
    p_an.add_argument('--lengths', type=int, default=flying_space.N_LENGTHS,
                      help='tether lengths per position (480)')
    p_an.add_argument('--out', type=Path, default=Path('runs/catenary-analyze'), help='output directory')
    p_ref = sub.add_parser('reference', help='reference-length model vs exact (Sec. 4.3)')
    p_ref.add_argument('--out', type=Path, default=Path('runs/catenary-reference'), help='output directory')


def _command(args: argparse.Namespace) -> str:
    if args.command == 'reference':
        return reference(args)
    if args.step is not None and not 0.0 < args.step <= args.extent:
        raise UsageError(f'--step must be in (0, extent] (got {args.step})')
    if args.lengths < 10:
        raise UsageError(f'--lengths must be at least 10 (got {args.lengths})')
    return analyze(args)


COMMAND = Command('catenary statics, heave robustness, flying space (thesis Ch. 3-4)', _arguments,
                  analysis(PROG, _command))
