"""UAV-surrogate report (thesis Sec. 5.1, 6.1, Fig. 6.1-6.4) from recorded runs.

``tethersim report surrogate BAG...`` reads runs of the ``surrogate_catenary``,
``surrogate_taut`` and ``surrogate_locked`` scenes (any subset, any order: each run is
recognised by the reel mode it recorded) and writes:

* ``surrogate_length.png`` (Fig. 6.1): deployed length of each run against the catenary
  reference model of the true relative position, platform heave, and the length error;
* ``surrogate_angles.png`` (Fig. 6.2, 6.3): arrival angle measured vs the catenary theory
  for the measured length and relative position, and the guide-arm reading with its
  dead-band vs the theoretical departure angle, with their normalised cross-correlation;
* ``surrogate_tension.png`` (Fig. 6.4): tension at the UAV end of each run given (the thesis: catenary vs taut);
* ``surrogate_clearance.png``: lowest point above the deck and the sea, per run
  (:mod:`tether_dynamics.clearance`: the deck is the reel's ``guide_height`` below the guide way);
* ``summary.txt``: the table beside the thesis's numbers and the issue's acceptance checks.

Definitions (each as in the thesis where it says): length error = encoder length
(/reel/state) minus the reference model (Eq. 4.4/4.5) of the true relative position
(/truth/relative); tension = plant tension at the UAV end (the surrogate's load cell);
arrival-angle error = mean |β measured - β of the static catenary with the measured length|;
departure lag = lag of the peak of the normalised cross-correlation between the guide-arm
reading and the theoretical departure angle (positive: the reading lags). Statistics skip
the first ``settle`` seconds (``--settle``; by default ``SETTLE``, the platform's ramp-in, or
half the run if it is shorter than twice that).
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from tether_bringup.bag_reader import Bag
from tether_bringup.bag_reader import read_bag
from tether_bringup.errors import BagError
from tether_common.command_line import Command
from tether_common.command_line import UsageError
from tether_common.command_line import analysis
from tether_common.correlation import cross_correlation
from tether_dynamics.clearance import above_deck
from tether_dynamics.clearance import guide_height
from tether_common.report_figures import ReportLines
from tether_dynamics.statics.catenary import solve
from tether_dynamics.statics.reference_length import reference_lengths

SETTLE = 10.0
"""s skipped at the start of each run by default."""
THESIS = {
    'length_mean': 0.022, 'length_rmse': 0.028, 'tension_catenary': (2.38, 0.27, 2.21),
    'tension_taut': (27.52, 7.30, 55.70), 'arrival_error': 2.1, 'departure_lag': 0.88,
}
"""Sec. 6.1.1-6.1.4."""
THESIS_TABLE_6_2 = {'length_mean': 0.022, 'length_rmse': 0.027, 'test_time': 2465.0}
"""Length error with the relative-altitude estimator as the reel's feedback (Table 6.2)."""
MODE_NAMES = {1: 'catenary', 2: 'taut', 5: 'locked'}
TOPICS = ('/tether/state', '/truth/relative', '/reel/state', '/reel/diagnostics', '/platform/state')


@dataclass
class Run:
    """Time series of one run, each on its own stamps (s)."""

    path: Path
    controller: str
    profile: str
    tether: dict[str, np.ndarray]
    relative: dict[str, np.ndarray]
    reel: dict[str, np.ndarray]
    diagnostics: dict[str, np.ndarray]
    platform: dict[str, np.ndarray]


def platform_profile(path: str | Path) -> str:
    """The platform's motion profile and seed of a run, from the run directory's ``params/platform.yaml``.

    ``path`` may be the run directory, its bag directory or the ``.mcap`` file; ``'unknown'``
    when no parameter file of the run is found (a bag copied out of its run directory).
    """
    start = Path(path).resolve()
    for directory in (start, *start.parents[:2]):
        file = directory / 'params' / 'platform.yaml'
        if file.is_file():
            try:
                values = yaml.safe_load(file.read_text())['/**']['ros__parameters']
            except (yaml.YAMLError, KeyError, TypeError):
                return 'unknown'
            return f'{values.get("profile", "jonswap")} seed {values.get("seed", 1)}'
    return 'unknown'


def _stamp(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def _rows(bag: Bag, topic: str, fields) -> dict[str, np.ndarray]:
    rows = []
    for _, m in bag.decoded(topic, required=False):
        rows.append([_stamp(m)] + [f(m) for f in fields.values()])
    data = np.array(rows, dtype=float).reshape(-1, len(fields) + 1)
    order = np.argsort(data[:, 0], kind='stable')
    data = data[order]
    return {'t': data[:, 0], **{name: data[:, i + 1] for i, name in enumerate(fields)}}


def load_run(path: str | Path) -> Run:
    """Read one run's bag (a file, bag directory or run directory)."""
    try:
        bag = read_bag(path)
        present = set(bag.topics)
        missing = [t for t in TOPICS[:4] if t not in present]
        if missing:
            raise UsageError(f'{path}: not a surrogate run, no {", ".join(missing)} in the bag')
        tether = _rows(bag, '/tether/state', {
            'length': lambda m: m.deployed_length, 'tension_uav': lambda m: m.tension_uav,
            'tension_reel': lambda m: m.tension_reel, 'departure': lambda m: m.departure_angle,
            'arrival': lambda m: m.arrival_angle, 'clearance_deck': lambda m: m.clearance_deck,
            'clearance_sea': lambda m: m.clearance_sea, 'fouling': lambda m: float(m.fouling),
            'lowest_z': lambda m: m.lowest_point.z})
        relative = _rows(bag, '/truth/relative', {
            'dr': lambda m: math.hypot(m.position.x, m.position.y), 'dz': lambda m: m.position.z})
        reel = _rows(bag, '/reel/state', {
            'length': lambda m: m.deployed_length, 'arm': lambda m: m.guide_arm_angle,
            'mode': lambda m: m.mode, 'payout': lambda m: m.payout_rate,
            'tension_estimate': lambda m: m.tension_estimate})
        diagnostics = _rows(bag, '/reel/diagnostics', {
            'trips': lambda m: m.trip_count, 'reference': lambda m: m.reference_length,
            'filtered': lambda m: m.filtered_reference_length, 'alpha': lambda m: m.filter_alpha})
        platform = (_rows(bag, '/platform/state', {'heave': lambda m: m.heave})
                    if '/platform/state' in present else {'t': np.zeros(0), 'heave': np.zeros(0)})
    except BagError as error:
        raise UsageError(f'{path}: cannot read the bag: {error}') from None
    if len(reel['t']) == 0 or len(tether['t']) == 0:
        raise UsageError(f'{path}: the bag holds no /reel/state or /tether/state messages')
    modes = reel['mode'][reel['mode'] != 4]  # fault: a safety trip, not the controller
    controller = MODE_NAMES.get(int(np.bincount(modes.astype(int)).argmax()) if len(modes) else 4)
    if controller is None:
        raise UsageError(f'{path}: the reel ran no catenary, taut or locked mode (/reel/state mode)')
    return Run(Path(path), controller, platform_profile(path), tether, relative, reel, diagnostics, platform)


def _on(t_from: np.ndarray, values: np.ndarray, t_to: np.ndarray) -> np.ndarray:
    return np.interp(t_to, t_from, values)


def _lag(t: np.ndarray, measured: np.ndarray, theory: np.ndarray,
         max_lag: float = 5.0) -> tuple[float, np.ndarray, np.ndarray]:
    """Lag (s) of the normalised cross-correlation's peak (positive when ``measured`` lags), the lags (s)
    and the correlation at each.
    """
    dt = float(np.median(np.diff(t)))
    n = len(measured)
    k = min(int(max_lag / dt), n // 2)
    lags, corr = cross_correlation(theory, measured)
    keep = np.abs(lags) <= k
    lags, corr = lags[keep], corr[keep]
    return float(lags[np.argmax(corr)] * dt), lags * dt, corr


def analyse(run: Run, settle: float | None = None) -> dict:
    """Figures of one run after its first ``settle`` seconds (see the module docstring for definitions)."""
    t = run.tether['t']
    if settle is None:
        settle = min(SETTLE, 0.5 * (t[-1] - t[0]))
    if t[-1] - t[0] < settle + 1.0:
        raise UsageError(f'{run.path}: {t[-1] - t[0]:.1f} s recorded, too short to skip {settle:g} s and keep 1 s '
                         '(see --settle)')
    keep = t >= t[0] + settle
    dr = _on(run.relative['t'], run.relative['dr'], t)
    dz = _on(run.relative['t'], run.relative['dz'], t)
    model, _ = reference_lengths(dr, dz, 'poly')
    measured = _on(run.reel['t'], run.reel['length'], t)
    error = measured - model
    tension = run.tether['tension_uav']
    length = np.maximum(run.tether['length'], np.hypot(dr, dz) * (1 + 1e-9))
    theory = solve(dr, dz, length)
    arm_t = run.reel['t']
    arm_keep = (arm_t >= t[0] + settle) & np.isfinite(run.reel['arm'])
    alpha_theory = _on(t, theory.alpha, arm_t[arm_keep])
    lag, lags, corr = (_lag(arm_t[arm_keep], run.reel['arm'][arm_keep], alpha_theory)
                       if arm_keep.sum() > 10 else (math.nan, np.zeros(0), np.zeros(0)))
    deck = above_deck(run.tether['clearance_deck'], guide_height(run.path))
    fouled = (deck < 0.0) | (run.tether['fouling'] > 0.5)
    return {
        't': t, 'deck': deck, 'model': model, 'measured': measured, 'error': error, 'keep': keep, 'tension': tension,
        'beta_theory': theory.beta, 'alpha_theory': theory.alpha, 'lags': lags, 'corr': corr,
        'length_mean': float(np.mean(error[keep])), 'length_rmse': float(np.sqrt(np.mean(error[keep] ** 2))),
        'tension_stats': (float(np.mean(tension[keep])), float(np.std(tension[keep])), float(np.ptp(tension[keep]))),
        'arrival_error': float(np.degrees(np.mean(np.abs(run.tether['arrival'][keep] - theory.beta[keep])))),
        'departure_lag': lag,
        'trips': int(np.max(run.diagnostics['trips'])) if len(run.diagnostics['trips']) else 0,
        'min_deck': float(np.min(deck[keep])), 'min_sea': float(np.min(run.tether['clearance_sea'][keep])),
        'fouled_time': float(np.sum(fouled[keep]) * np.median(np.diff(t))),
        'first_fouled': float(t[np.argmax(fouled)] - t[0]) if fouled.any() else math.nan,
        'duration': float(t[-1] - t[0]), 'settle': settle,
    }


def _row(name: str, thesis: str, values: dict[str, str]) -> str:
    """One table row: a column per run given, in the order catenary, taut, locked."""
    cells = ''.join(f'{values[c]:>22}' for c in MODE_NAMES.values() if c in values)
    return f'{name:<34}{thesis:>22}{cells}'


def report(paths: list[str], out: Path, settle: float | None = None) -> str:
    """Analyse the runs, write the PNGs and return the summary text."""
    return report_runs([load_run(p) for p in paths], out, settle)[0]


def report_runs(runs: list[Run], out: Path, settle: float | None = None) -> tuple[str, dict[str, dict]]:
    """Analyse the runs, write the PNGs; return the summary text and each run's :func:`analyse` by controller."""
    by_mode: dict[str, tuple[Run, dict]] = {}
    for run in runs:
        if run.controller in by_mode:
            raise UsageError(f'two {run.controller} runs given: {by_mode[run.controller][0].path} and {run.path}')
        by_mode[run.controller] = (run, analyse(run, settle))
    profiles = {run.profile for run in runs}
    if len(profiles) > 1:
        raise UsageError('the runs played different platform profiles (' + ', '.join(
            f'{run.controller}: {run.profile}' for run in runs) + '); compare runs of one profile')
    by_mode = {mode: by_mode[mode] for mode in MODE_NAMES.values() if mode in by_mode}
    figures = {mode: result for mode, (_, result) in by_mode.items()}
    fmt = {
        'length mean error (m)': lambda r: f'{r["length_mean"]:+.4f}',
        'length RMSE (m)': lambda r: f'{r["length_rmse"]:.4f}',
        'tension at UAV mean ± std (N)': lambda r: f'{r["tension_stats"][0]:.2f} ± {r["tension_stats"][1]:.2f}',
        'tension peak-to-peak (N)': lambda r: f'{r["tension_stats"][2]:.2f}',
        'arrival-angle error (deg)': lambda r: f'{r["arrival_error"]:.2f}',
        'departure-angle xcorr lag (s)': lambda r: f'{r["departure_lag"]:.2f}',
        'safety trips': lambda r: f'{r["trips"]}',
        'lowest point above deck, min (m)': lambda r: f'{r["min_deck"]:.3f}',
        'lowest point above sea, min (m)': lambda r: f'{r["min_sea"]:.3f}',
        'time fouled (s)': lambda r: f'{r["fouled_time"]:.1f}',
    }
    thesis = {
        'length mean error (m)': f'{THESIS["length_mean"]}', 'length RMSE (m)': f'{THESIS["length_rmse"]}',
        'tension at UAV mean ± std (N)': '2.38 ± 0.27 / 27.52 ± 7.30', 'tension peak-to-peak (N)': '2.21 / 55.70',
        'arrival-angle error (deg)': f'{THESIS["arrival_error"]}',
        'departure-angle xcorr lag (s)': f'{THESIS["departure_lag"]}',
    }
    lines = [f'UAV-surrogate experiment (Sec. 5.1, 6.1), platform profile {runs[0].profile}: '
             + ', '.join(f'{m} {figures[m]["duration"]:.0f} s, statistics after {figures[m]["settle"]:.1f} s '
                         f'({by_mode[m][0].path})' for m in figures),
             _row('', 'thesis (cat. / taut)', {m: m for m in figures})]
    for name, f in fmt.items():
        lines.append(_row(name, thesis.get(name, ''), {m: f(r) for m, r in figures.items()}))
    if 'catenary' in figures and 'taut' in figures:
        ratio = figures['taut']['tension_stats'][0] / figures['catenary']['tension_stats'][0]
        lines.append(f'mean tension taut/catenary: {ratio:.1f}x (thesis {27.52 / 2.38:.1f}x)')
    lines += _checks(figures)
    _plots(out, by_mode)
    lines.append('plots: ' + ', '.join(str(out / n) for n in ('surrogate_length.png', 'surrogate_angles.png',
                                                               'surrogate_tension.png', 'surrogate_clearance.png')))
    return '\n'.join(lines), figures


def _checks(figures: dict[str, dict]) -> list[str]:
    """The acceptance checks of the surrogate experiment, each computed from the runs given."""
    lines = []

    def check(ok: bool, text: str) -> None:
        lines.append(f'{"PASS" if ok else "FAIL"}: {text}')

    if 'catenary' in figures:
        c = figures['catenary']
        check(c['length_rmse'] <= 0.03, f'catenary length RMSE {c["length_rmse"]:.4f} m <= 0.03 m')
    if 'catenary' in figures and 'taut' in figures:
        ratio = figures['taut']['tension_stats'][0] / figures['catenary']['tension_stats'][0]
        check(ratio >= 10.0, f'mean tension taut/catenary {ratio:.1f}x >= 10x')
    for mode in ('catenary', 'taut'):
        if mode in figures:
            check(figures[mode]['trips'] == 0, f'{mode}: {figures[mode]["trips"]} safety trips (none expected)')
    if 'locked' in figures:
        f = figures['locked']
        check(f['fouled_time'] > 0.0, f'no control: fouled for {f["fouled_time"]:.1f} s, first at '
              f'{f["first_fouled"]:.1f} s (lowest point below the deck or in the sea)')
    return lines


def _plots(out: Path, by_mode: dict[str, tuple[Run, dict]]) -> None:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    colors = {'catenary': 'tab:blue', 'taut': 'tab:red', 'locked': 'tab:gray'}
    fig, axes = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    for mode, (run, r) in by_mode.items():  # noqa: B007 - the last run also labels the figure below
        t = r['t'] - r['t'][0]
        axes[0].plot(t, r['measured'], color=colors[mode], label=f'{mode}: measured length')
        axes[0].plot(t, r['model'], color=colors[mode], ls=':', lw=1, label=f'{mode}: catenary model')
        axes[1].plot(t, r['error'], color=colors[mode], label=mode)
    first = next(iter(by_mode.values()))[0]
    if len(first.platform['t']):
        ax2 = axes[0].twinx()
        ax2.plot(first.platform['t'] - first.tether['t'][0], first.platform['heave'], color='k', lw=0.6, alpha=0.5)
        ax2.set_ylabel('platform heave (m)')
    axes[0].set_ylabel('tether length (m)')
    axes[0].legend(fontsize=7, loc='upper left')
    axes[1].set_ylabel('measured - model (m)')
    axes[1].set_xlabel('t (s)')
    axes[1].legend(fontsize=8, loc='upper right')
    axes[0].set_title('Tether length against the catenary model (cf. Fig. 6.1)')
    fig.tight_layout()
    fig.savefig(out / 'surrogate_length.png', dpi=100)
    plt.close(fig)

    fig, axes = plt.subplots(3, 1, figsize=(11, 9))
    for mode, (run, r) in by_mode.items():  # noqa: B007 - the last run also labels the figure below
        t = r['t'] - r['t'][0]
        axes[0].plot(t, np.degrees(run.tether['arrival']), color=colors[mode], label=f'{mode}: measured β')
        if mode == 'catenary':
            axes[0].plot(t, np.degrees(r['beta_theory']), 'k:', label='catenary theory β')
            axes[1].plot(run.reel['t'] - r['t'][0], np.degrees(run.reel['arm']), color=colors[mode],
                         label='guide-arm reading')
            axes[1].plot(t, np.degrees(r['alpha_theory']), 'k:', label='catenary theory')
            axes[2].plot(r['lags'], r['corr'], color=colors[mode], label='guide-arm reading vs theory')
            axes[2].axvline(r['departure_lag'], color='k', lw=0.6, label=f'peak: lag {r["departure_lag"]:.2f} s')
            axes[2].legend(fontsize=8, loc='upper right')
    axes[0].set_ylabel('arrival angle (deg)')
    axes[0].legend(fontsize=8, loc='upper right')
    axes[0].set_title('Arrival angle (cf. Fig. 6.2) and departure angle with the guide-arm dead-band (cf. Fig. 6.3)')
    axes[1].set_ylabel('departure angle (deg)')
    axes[1].set_xlabel('t (s)')
    axes[1].legend(fontsize=8, loc='upper right')
    axes[2].set_xlabel('lag of the reading (s)')
    axes[2].set_ylabel('normalised xcorr')
    fig.tight_layout()
    fig.savefig(out / 'surrogate_angles.png', dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(11, 4.5))
    for mode, (run, r) in by_mode.items():  # noqa: B007 - the last run also labels the figure below
        ax.plot(r['t'] - r['t'][0], r['tension'], color=colors[mode], label=mode)
    ax.set_yscale('log')
    ax.set_ylabel('tension at the UAV (N)')
    ax.set_xlabel('t (s)')
    ax.set_title(f'Tether tension at the UAV surrogate: {", ".join(by_mode)} (cf. Fig. 6.4)')
    ax.legend(loc='upper right')
    fig.tight_layout()
    fig.savefig(out / 'surrogate_tension.png', dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(11, 4.5))
    for mode, (run, r) in by_mode.items():  # noqa: B007 - the last run also labels the figure below
        t = r['t'] - r['t'][0]
        ax.plot(t, r['deck'], color=colors[mode], label=f'{mode}: above the deck')
        ax.plot(t, run.tether['clearance_sea'], color=colors[mode], ls='--', label=f'{mode}: above sea')
    ax.axhline(0.0, color='k', lw=0.8)
    ax.set_ylabel('lowest point clearance (m)')
    ax.set_xlabel('t (s)')
    ax.set_title('Fouling clearance of the lowest point (deck: the reel\'s guide_height below the guide way)')
    ax.legend(fontsize=8, loc='upper right')
    fig.tight_layout()
    fig.savefig(out / 'surrogate_clearance.png', dpi=100)
    plt.close(fig)


def figures(run: Run, result: dict) -> dict:
    """One run's figures as data, from :func:`analyse` (after the settling time); ``success``: no safety trip
    and no time fouled.
    """
    keep = result['keep']
    return {
        'controller': run.controller, 'profile': run.profile,
        'success': result['trips'] == 0 and result['fouled_time'] == 0.0,
        'length_mean': result['length_mean'], 'length_rmse': result['length_rmse'],
        'tension_uav_mean': result['tension_stats'][0], 'tension_uav_std': result['tension_stats'][1],
        'peak_tension_uav': float(np.max(run.tether['tension_uav'][keep])),
        'peak_tension_reel': float(np.max(run.tether['tension_reel'][keep])),
        'arrival_error': result['arrival_error'], 'departure_lag': result['departure_lag'],
        'reel_trips': result['trips'], 'fouled_time': result['fouled_time'],
        'least_clearance_deck': result['min_deck'], 'least_clearance_sea': result['min_sea'],
    }


def reel_report(bag_path: str, out_dir: str) -> ReportLines:
    """Scene report: the figures of one run (length error, tension, trips, clearance, Sec. 6.1), as text and as
    data (:func:`figures`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    run = load_run(bag_path)
    text, results = report_runs([run], out)
    return ReportLines(text.splitlines(), figures(run, results[run.controller]))


def estimator_feedback_report(bag_path: str, out_dir: str) -> ReportLines:
    """Scene report of ``surrogate_estimator``: the length error of :func:`analyse` beside Table 6.2."""
    result = analyse(load_run(bag_path))
    thesis = THESIS_TABLE_6_2
    return ReportLines([f'length error with the estimator as feedback (Table 6.2), after the first {result["settle"]:g} s: '
            f'mean {result["length_mean"]:+.4f} m, RMSE {result["length_rmse"]:.4f} m over '
            f'{result["duration"] - result["settle"]:.0f} s; thesis: mean {thesis["length_mean"]} m, RMSE '
            f'{thesis["length_rmse"]} m over {thesis["test_time"]:.0f} s (MoCap feedback, Sec. 6.1.1: mean '
            f'{THESIS["length_mean"]} m, RMSE {THESIS["length_rmse"]} m)'],
        {'length_mean': result['length_mean'], 'length_rmse': result['length_rmse']})


def _arguments(parser: argparse.ArgumentParser) -> None:
    """Add the arguments of ``tethersim report surrogate`` to its parser."""
    parser.add_argument('bags', nargs='+', help='run directories, bag directories or .mcap files')
    parser.add_argument('--out', type=Path, default=Path('runs/report-surrogate'), help='output directory')
    parser.add_argument('--settle', type=float, default=None,
                        help=f's skipped at the start of each run (default {SETTLE:g}, or half a shorter run)')


def _command(args: argparse.Namespace) -> str:
    if args.settle is not None and args.settle < 0.0:
        raise UsageError(f'--settle must be >= 0 s, got {args.settle:g}')
    return report(args.bags, args.out, args.settle)


COMMAND = Command('UAV-surrogate experiment (Sec. 6.1, Fig. 6.1-6.4) from surrogate_* runs',
                  _arguments, analysis('tethersim report surrogate', _command))

