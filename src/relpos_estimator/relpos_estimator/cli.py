"""``tethersim estimator``: Twiddle tuning and replay evaluation of the relative-altitude estimator.

Subcommands:
    evaluate   run the estimator over recorded sensor topics; Table 6.1 figures and per-fault counts
               (``--replay``: the estimator node runs behind ``tethersim replay`` of each recording)
    tune       Algorithm 1 (Sec. 5.2) on recordings; writes the tuned covariances as a parameter file
    measure    Q and R measured from recordings' sensors against their truth (relpos_estimator.noise);
               writes them as a parameter file
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

from relpos_estimator.estimator import Estimator  # noqa: E402
from relpos_estimator.estimator_params import PARAMETERS  # noqa: E402
from relpos_estimator.estimator_params import configs  # noqa: E402
from relpos_estimator.estimator_params import tuned_file  # noqa: E402
from relpos_estimator.kalman import Covariances  # noqa: E402
from relpos_estimator.noise import measured_covariances  # noqa: E402
from relpos_estimator.recorded import Recording  # noqa: E402
from relpos_estimator.recorded import read_outputs  # noqa: E402
from relpos_estimator.recorded import read_recording  # noqa: E402
from relpos_estimator.recorded import replay  # noqa: E402
from relpos_estimator.recorded import rmse  # noqa: E402
from relpos_estimator.recorded import score  # noqa: E402
from relpos_estimator.report import THESIS_TABLE_6_1  # noqa: E402
from relpos_estimator.twiddle import twiddle  # noqa: E402
from tether_bringup.bag_reader import ALLOW_OPTION  # noqa: E402
from tether_bringup.bag_reader import damaged_bags_allowed  # noqa: E402
from tether_bringup.report_command import report_skipped  # noqa: E402
from tether_common.command_line import Command  # noqa: E402
from tether_common.command_line import OneLineParser  # noqa: E402
from tether_common.command_line import UsageError  # noqa: E402
from tether_common.command_line import analysis  # noqa: E402
from tether_common.command_line import dispatch  # noqa: E402
from tether_common.command_line import positive  # noqa: E402
from tether_common.parameters import spec_table  # noqa: E402

PROG = 'tethersim estimator'
REPLAYED = ('/imu/reel', '/imu/uav', '/dgps/fix')
"""The topics the estimator node consumes, replayed to it by ``evaluate --replay``."""
FAULT_SHIFT_LIMIT = 0.05
"""m, the largest estimate shift a fault may cause (issue's acceptance)."""


def load_parameters(path: Path | None) -> dict:
    """Estimator parameters: defaults, overridden by a ROS 2 parameter file (``/**`` or ``estimator`` section)."""
    values = {spec.name: spec.default for spec in PARAMETERS}
    if path is None:
        return values
    try:
        document = yaml.safe_load(path.read_text(encoding='utf-8')) or {}
    except (OSError, yaml.YAMLError) as error:
        raise UsageError(f'{path}: cannot read the parameter file: {error}') from None
    section = next((document[k] for k in ('/**', 'estimator', '/estimator') if k in document), None)
    if not isinstance(section, dict) or not isinstance(section.get('ros__parameters'), dict):
        raise UsageError(f'{path}: expected a ROS 2 parameter file with /** or estimator: ros__parameters:')
    table = spec_table(PARAMETERS)
    for name, value in section['ros__parameters'].items():
        spec = table.get(name)
        if spec is None:
            raise UsageError(f'{path}: unknown estimator parameter {name!r}')
        reason = spec.check(value)
        if reason:
            raise UsageError(f'{path}: {name}: {reason}')
        values[name] = spec.coerce(value)
    return values


def _factory(values: dict, covariances: Covariances | None = None):
    cov, logic = configs(values)
    cov = covariances or cov
    return lambda: Estimator(cov, logic, values['rate'], 1.0 / values['dgps_rate'])


def _recordings(paths: list[str]):
    recs = []
    for i, path in enumerate(paths, 1):
        print(f'[{PROG}] reading {path} ({i}/{len(paths)})', file=sys.stderr, flush=True)
        recs.append(read_recording(Path(path)))
    return recs


def _through_replay(rec: Recording, bag: str, values: dict, out: Path, allow_damaged: bool = False):
    """Replay the recording's sensor topics to the estimator node with ``values``; its recorded outputs."""
    out.mkdir(parents=True, exist_ok=True)
    scene = out / f'replay-{rec.name}.yaml'
    scene.write_text(yaml.safe_dump({
        'description': f'estimator node replayed {rec.name}',
        'nodes': {'estimator': {'package': 'relpos_estimator', 'executable': 'estimator', 'parameters': values}},
    }, sort_keys=False), encoding='utf-8')
    run_dir = out / f'replay-{rec.name}'
    if run_dir.exists():
        raise UsageError(f'{run_dir} exists: remove it or give another --out')
    command = [sys.executable, '-m', 'tether_bringup', 'replay', bag, '--topics', *REPLAYED, '--scene', str(scene),
               '--rate', 'max', '--out', str(run_dir), *([ALLOW_OPTION] if allow_damaged else [])]
    print(f'[{PROG}] {" ".join(command[2:])}', file=sys.stderr, flush=True)
    result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
    if result.returncode != 0:
        last = (result.stderr.strip().splitlines() or ['no output'])[-1]
        raise UsageError(f'tethersim replay of {bag} failed (exit {result.returncode}): {last}')
    return read_outputs(run_dir)


def cmd_evaluate(args: argparse.Namespace) -> str:
    """Score the estimator on each recording; Table 6.1 layout plus per-fault counts."""
    values = load_parameters(args.params)
    recs = _recordings(args.bags)
    scores = []
    for i, (rec, bag) in enumerate(zip(recs, args.bags), 1):
        print(f'[{PROG}] evaluating {rec.name} ({i}/{len(recs)})', file=sys.stderr, flush=True)
        run = (_through_replay(rec, bag, values, args.out, args.allow_damaged) if args.replay
               else replay(rec, _factory(values)(), input_delay=values['input_delay']))
        scores.append(score(rec, run, _factory(values), counterfactuals=not args.no_shift))
    source = ('the estimator node behind tethersim replay of each recording' if args.replay
              else 'the estimator core stepped directly on the decoded messages')
    lines = ['Estimator vs first-order hold (FOH) against the recorded truth (thesis Table 6.1 layout)',
             f'outputs of {source}; parameters: {args.params}',
             f'{"recording":24s} {"time s":>8s} {"filter mean mm":>15s} {"filter RMSE mm":>15s} '
             f'{"FOH mean mm":>12s} {"FOH RMSE mm":>12s} {"RMSE ratio":>10s}']
    for s in scores:
        lines.append(f'{s.name:24s} {s.test_time:8.1f} {s.filter_mean * 1e3:15.3f} {s.filter_rmse * 1e3:15.3f} '
                     f'{s.foh_mean * 1e3:12.3f} {s.foh_rmse * 1e3:12.3f} {s.filter_rmse / s.foh_rmse:10.3f}')
    lines.append('thesis Table 6.1 (4 Hz de-rated MoCap, no faults):')
    for name, (fm, fr, hm, hr) in THESIS_TABLE_6_1.items():
        lines.append(f'{name:24s} {"":8s} {fm * 1e3:15.2f} {fr * 1e3:15.2f} {hm * 1e3:12.2f} {hr * 1e3:12.2f} '
                     f'{fr / hr:10.2f}')
    lines.append('')
    lines.append('Faults per recording: injected, rejected, fused, largest estimate shift (mm; against the run '
                 'with the faulty messages replaced by clean ones at their truth)')
    for s in scores:
        if not s.faults:
            lines.append(f'{s.name}: no faults injected')
        for kind, (n, rejected, fused, shift) in s.faults.items():
            shift_text = 'n/a' if np.isnan(shift) else f'{shift * 1e3:.1f}'
            lines.append(f'{s.name:24s} {kind:18s} injected {n:4d}  rejected {rejected:4d}  fused {fused:4d}  '
                         f'largest shift {shift_text} mm')
    lines.append('')
    lines += _checks(scores)
    fig, ax = plt.subplots(figsize=(8, 4))
    x = np.arange(len(scores))
    ax.bar(x - 0.2, [s.filter_rmse * 1e3 for s in scores], 0.4, label='filter')
    ax.bar(x + 0.2, [s.foh_rmse * 1e3 for s in scores], 0.4, label='FOH')
    ax.set_xticks(x, [s.name for s in scores], rotation=20)
    ax.set_ylabel('RMSE (mm)')
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / 'evaluate.png', dpi=110)
    plt.close(fig)
    lines.append(f'plot: {args.out / "evaluate.png"}')
    return '\n'.join(lines)


def _checks(scores) -> list[str]:
    """The issue's acceptance checks, each computed from the scores: FOH/2, fault shifts, still profile."""
    lines = []
    for s in scores:
        if 'still' in s.name:
            ok = s.filter_rmse <= s.foh_rmse
            lines.append(f'{"PASS" if ok else "FAIL"}: {s.name}: filter RMSE {s.filter_rmse * 1e3:.3f} mm <= '
                         f'FOH RMSE {s.foh_rmse * 1e3:.3f} mm (zero motion: not worse than FOH)')
        else:
            ok = s.filter_rmse <= 0.5 * s.foh_rmse
            lines.append(f'{"PASS" if ok else "FAIL"}: {s.name}: filter RMSE {s.filter_rmse * 1e3:.3f} mm <= half '
                         f'the FOH\'s {s.foh_rmse * 1e3:.3f} mm')
        shifts = {k: v[3] for k, v in s.faults.items() if not np.isnan(v[3])}
        if shifts:
            kind = max(shifts, key=lambda k: shifts[k])
            ok = shifts[kind] <= FAULT_SHIFT_LIMIT
            lines.append(f'{"PASS" if ok else "FAIL"}: {s.name}: largest fault shift {shifts[kind] * 1e3:.1f} mm '
                         f'({kind}) <= {FAULT_SHIFT_LIMIT * 1e3:.0f} mm')
    return lines


def cmd_tune(args: argparse.Namespace) -> str:
    """Algorithm 1 on the recordings' RMSE; writes tuned.yaml (ROS 2 parameter file for the estimator node)."""
    values = load_parameters(args.params)
    recs = _recordings(args.bags)
    names = Covariances.names()
    start = np.array([values[n] for n in names], dtype=float)
    evaluations = [0]
    t0 = time.monotonic()

    def cost(p: np.ndarray) -> float:
        evaluations[0] += 1
        return rmse(recs, _factory(values, Covariances(*p)))

    def progress(rounds: int, best: float, p: np.ndarray) -> None:
        print(f'[{PROG} tune] round {rounds}: RMSE {best * 1e3:.3f} mm after {evaluations[0]} runs, '
              f'{time.monotonic() - t0:.0f} s', file=sys.stderr, flush=True)

    initial = cost(start)
    tuned, best, rounds = twiddle(cost, start, start * args.step, tolerance=args.tolerance,
                                  max_rounds=args.max_rounds, progress=progress)
    document = {'/**': {'ros__parameters': {n: float(v) for n, v in zip(names, tuned)}}}
    path = args.out / 'tuned.yaml'
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding='utf-8')
    lines = [f'Twiddle (Algorithm 1) on {len(recs)} recording(s): RMSE {initial * 1e3:.3f} mm -> {best * 1e3:.3f} mm '
             f'in {rounds} rounds, {evaluations[0]} filter runs'
             + ('' if rounds < args.max_rounds else f' (stopped at --max-rounds {args.max_rounds})'),
             f'{"parameter":12s} {"start":>12s} {"tuned":>12s} {"thesis Sec. 6.2":>16s}']
    thesis = Covariances()
    for n, a, b in zip(names, start, tuned):
        lines.append(f'{n:12s} {a:12.4g} {b:12.4g} {getattr(thesis, n):16.4g}')
    lines.append(f'parameter file: {path} (ros2 run relpos_estimator estimator --ros-args --params-file {path}; '
                 f'tethersim estimator evaluate --params {path} BAG...)')
    return '\n'.join(lines)


def cmd_measure(args: argparse.Namespace) -> str:
    """Measure Q and R on the recordings (relpos_estimator.noise); write them as a parameter file."""
    recs = _recordings(args.bags)
    measured = measured_covariances(recs)
    names = Covariances.names()
    source = 'tethersim estimator measure ' + ' '.join(Path(b).name for b in args.bags)
    document = {'/**': {'ros__parameters': {n: float(getattr(measured, n)) for n in names}}}
    path = args.out / 'measured.yaml'
    path.write_text(f'# Q and R measured by {source} (relpos_estimator.noise)\n'
                    + yaml.safe_dump(document, sort_keys=False), encoding='utf-8')
    thesis = Covariances()
    lines = [f'Q and R measured on {len(recs)} recording(s) (sensors against the recorded truth)',
             f'{"parameter":12s} {"measured":>12s} {"thesis Sec. 6.2":>16s}']
    lines += [f'{n:12s} {getattr(measured, n):12.4g} {getattr(thesis, n):16.4g}' for n in names]
    lines.append(f'parameter file: {path} (tethersim estimator evaluate --params {path} BAG...)')
    return '\n'.join(lines)


def _arguments(parser: argparse.ArgumentParser) -> None:
    """Add the subcommands of ``tethersim estimator`` to its parser."""
    commands = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)
    evaluate = commands.add_parser('evaluate', help='score the estimator on recorded sensor topics (Table 6.1)')
    evaluate.add_argument('bags', nargs='+', help='bag files, bag directories or run directories')
    evaluate.add_argument('--params', type=Path, default=tuned_file(),
                          help='estimator parameter file (default: the tuned config/estimator_tuned.yaml)')
    evaluate.add_argument('--no-shift', action='store_true', help='skip the counterfactual runs of the shifts')
    evaluate.add_argument('--replay', action='store_true',
                          help='score the estimator node run behind tethersim replay of each recording')
    evaluate.add_argument('--out', type=Path, default=Path('runs/estimator-evaluate'), help='output directory')
    evaluate.add_argument(ALLOW_OPTION, action='store_true',
                          help='read what is intact in damaged bags and say what was skipped')
    evaluate.set_defaults(func=cmd_evaluate)
    tune = commands.add_parser('tune', help='Twiddle the covariances against the recorded truth (Algorithm 1)')
    tune.add_argument('bags', nargs='+', help='bag files, bag directories or run directories')
    tune.add_argument('--params', type=Path, help="start from this estimator parameter file (default: the "
                      "node's defaults, the thesis's Sec. 6.2 values)")
    tune.add_argument('--step', type=positive(), default=0.3, help='first step as a fraction of each value')
    tune.add_argument('--tolerance', type=positive(), default=0.1, help='stop at this mean relative step')
    tune.add_argument('--max-rounds', type=positive(int), default=30, help='stop after this many rounds')
    tune.add_argument('--out', type=Path, default=Path('runs/estimator-tune'), help='output directory')
    tune.add_argument(ALLOW_OPTION, action='store_true',
                      help='read what is intact in damaged bags and say what was skipped')
    tune.set_defaults(func=cmd_tune)
    measure = commands.add_parser('measure', help='measure Q and R from recorded sensors against the truth')
    measure.add_argument('bags', nargs='+', help='bag files, bag directories or run directories')
    measure.add_argument('--out', type=Path, default=Path('runs/estimator-measure'),
                         help='output directory (the parameter file is measured.yaml in it)')
    measure.set_defaults(func=cmd_measure)


_ANALYSIS = analysis(PROG, lambda args: args.func(args), user_errors=(ValueError,))


def _run(args: argparse.Namespace) -> int:
    """Run the subcommand; with --allow-damaged, say what was skipped of each damaged bag."""
    with damaged_bags_allowed(args.allow_damaged) as damaged:
        status = _ANALYSIS(args)
    return status if status else report_skipped(args, damaged)


COMMAND = Command('relative-altitude estimator: Twiddle tuning, replay evaluation (thesis Sec. 5.2, 6.2)',
                  _arguments, _run)


def main(argv: list[str] | None = None) -> int:
    """``tethersim estimator ARGS`` without the tethersim front end."""
    return dispatch('tethersim', {'estimator': lambda: COMMAND}, ['estimator', *(sys.argv[1:] if argv is None else argv)])


if __name__ == '__main__':
    sys.exit(main())
