"""``tethersim report campaign DIR``: a campaign's success rate, the distributions of its figures, its worst runs.

Reads the campaign directory's ``results.parquet`` (:mod:`tether_campaign.results`) and writes,
into ``--out`` (default ``DIR/report``):

* ``summary.txt``: the success rate with its 95 % Wilson score interval, over all runs and per
  level of each grid key; per numeric figure its count, mean,
  median, 95th percentile and extremes; the worst runs, each with the command that reruns it alone;
* ``figure_<name>.png``: per numeric figure, its histogram and empirical CDF over the runs.

A run succeeded when it finished (status ``ok``) and, where its reports give a ``success``
figure (the mission: landed on the pad; the surrogate: no trip, no time fouled), that is true.
Worst runs: the failed ones (with the reason), then those that did not succeed (with their
outcome and abort reason), then the highest of ``--worst`` (default ``peak_tension_reel``
where the runs have it), up to ``--count``.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

from tether_campaign.results import PARQUET  # noqa: E402
from tether_campaign.results import RUN_COLUMNS  # noqa: E402
from tether_campaign.results import read_table  # noqa: E402
from tether_campaign.sweep import STATE_FILE  # noqa: E402
from tether_common.command_line import Command  # noqa: E402
from tether_common.command_line import UsageError  # noqa: E402
from tether_common.command_line import analysis  # noqa: E402
from tether_common.command_line import positive  # noqa: E402

Z_95 = 1.959963984540054
"""The standard normal quantile of 0.975: a two-sided 95 % interval."""
DEFAULT_WORST = 'peak_tension_reel'
NOT_FIGURES = frozenset({*RUN_COLUMNS, 'exit_status', 'success'})


def wilson_interval(successes: int, runs: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (Wilson 1927; Brown, Cai and DasGupta 2001).

    The proportions the score test does not reject at ``z``::

        (p + z²/2n ± z sqrt(p(1-p)/n + z²/4n²)) / (1 + z²/n),  p = successes / runs

    Raises:
        ValueError: no runs, or successes outside [0, runs].
    """
    if runs <= 0 or not 0 <= successes <= runs:
        raise ValueError(f'{successes} successes of {runs} runs')
    p = successes / runs
    scale = 1.0 + z * z / runs
    centre = (p + z * z / (2 * runs)) / scale
    half = z * math.sqrt(p * (1 - p) / runs + z * z / (4 * runs * runs)) / scale
    # at p = 0 and p = 1 the interval's end is the proportion itself, exactly
    return (0.0 if successes == 0 else centre - half), (1.0 if successes == runs else centre + half)


def succeeded(row: dict) -> bool:
    """The run finished and, where it has a ``success`` figure, succeeded."""
    return row.get('status') == 'ok' and row.get('success') is not False


def _rate_line(label: str, rows: list[dict]) -> str:
    wins = sum(succeeded(row) for row in rows)
    low, high = wilson_interval(wins, len(rows))
    return f'{label}: {wins}/{len(rows)} succeeded, {100 * wins / len(rows):.1f} % (95 % Wilson {100 * low:.1f}-{100 * high:.1f} %)'


def factors(directory: Path) -> tuple[list[str], list[str]]:
    """The campaign's varied keys (``node.parameter`` or a scene key) and those of its grid, as its
    ``campaign.yaml`` records them.
    """
    try:
        state = yaml.safe_load((directory / STATE_FILE).read_text()) or {}
    except (OSError, yaml.YAMLError) as error:
        raise UsageError(f'{directory / STATE_FILE}: cannot read the campaign\'s record: {error}') from None
    return list(state.get('factors') or []), list(state.get('grid') or [])


def numeric_figures(rows: list[dict], varied: list[str]) -> list[str]:
    """The figure columns with a number in at least one row."""
    names = dict.fromkeys(name for row in rows for name in row)
    return [name for name in names if name not in NOT_FIGURES and name not in varied and any(
        isinstance(row.get(name), (int, float)) and not isinstance(row.get(name), bool) for row in rows)]


def _values(rows: list[dict], name: str) -> np.ndarray:
    return np.array([row[name] for row in rows if isinstance(row.get(name), (int, float))
                     and not isinstance(row.get(name), bool)], dtype=float)


def _plot(name: str, values: np.ndarray, out: Path) -> str:
    fig, (hist, ecdf) = plt.subplots(1, 2, figsize=(10, 3.6))
    hist.hist(values, bins=min(30, max(5, int(math.sqrt(len(values))) + 1)), color='tab:blue', alpha=0.8)
    hist.set_xlabel(name)
    hist.set_ylabel('runs')
    ordered = np.sort(values)
    ecdf.step(ordered, np.arange(1, len(ordered) + 1) / len(ordered), where='post')
    ecdf.set_xlabel(name)
    ecdf.set_ylabel('fraction of runs ≤ x')
    ecdf.set_ylim(0, 1.02)
    fig.suptitle(f'{name} over {len(values)} runs')
    fig.tight_layout()
    file = f'figure_{name.replace("/", "_")}.png'
    fig.savefig(out / file, dpi=90)
    plt.close(fig)
    return file


def worst_runs(rows: list[dict], by: str | None, count: int) -> list[tuple[dict, str]]:
    """The worst runs and why: failed, then not successful, then the highest ``by``; at most ``count``."""
    chosen: list[tuple[dict, str]] = []
    for row in rows:
        if row['status'] != 'ok':
            chosen.append((row, f'failed after {row["attempts"]} attempt(s): {row["reason"]}'))
    for row in rows:
        if row['status'] == 'ok' and not succeeded(row):
            why = f'outcome {row.get("outcome", "not successful")}'
            chosen.append((row, why + (f': {row["abort_reason"]}' if row.get('abort_reason') else '')))
    if by is not None:
        ranked = sorted((row for row in rows if isinstance(row.get(by), (int, float)) and row['status'] == 'ok'),
                        key=lambda row: row[by], reverse=True)
        chosen += [(row, f'{by} {row[by]:.4g}') for row in ranked if all(row is not c for c, _ in chosen)]
    return chosen[:count]


def report(directory: Path, out: Path, by: str | None = None, count: int = 5) -> str:
    """Analyse the campaign in ``directory``; write the PNGs into ``out``; return the summary text."""
    if not (directory / PARQUET).is_file():
        raise UsageError(f'{directory}: no {PARQUET} (not a campaign directory, or no run has finished yet)')
    rows = read_table(directory)
    if not rows:
        raise UsageError(f'{directory}: {PARQUET} holds no runs')
    varied, grid = factors(directory)
    figures = numeric_figures(rows, varied)
    if by is not None and by not in figures:
        raise UsageError(f'--worst {by}: not a numeric figure of the runs (figures: {", ".join(figures)})')
    by = by or (DEFAULT_WORST if DEFAULT_WORST in figures else None)
    failed = sum(row['status'] != 'ok' for row in rows)
    lines = [f'campaign {directory}: {len(rows)} runs, {len(rows) - failed} finished, {failed} failed',
             _rate_line('success rate', rows) + (' (success: finished and the reports\' success figure true)'
                                                 if any('success' in row for row in rows) else ' (success: finished)')]
    for factor in grid:
        levels = sorted({row.get(factor) for row in rows}, key=lambda v: (str(type(v)), v))
        if len(levels) > 1:
            lines.append(f'by {factor}:')
            lines += ['  ' + _rate_line(f'{level}', [row for row in rows if row.get(factor) == level])
                      for level in levels]
    outcomes = [row['outcome'] for row in rows if row.get('outcome') is not None]
    if outcomes:
        lines.append('outcomes: ' + ', '.join(f'{name} {outcomes.count(name)}' for name in sorted(set(outcomes))))
    lines.append(f'{"figure":<28} {"runs":>5} {"mean":>11} {"median":>11} {"p95":>11} {"min":>11} {"max":>11}')
    plots = []
    for name in figures:
        values = _values(rows, name)
        if not len(values):
            continue
        lines.append(f'{name:<28} {len(values):>5} {values.mean():>11.4g} {np.median(values):>11.4g} '
                     f'{np.percentile(values, 95):>11.4g} {values.min():>11.4g} {values.max():>11.4g}')
        plots.append(_plot(name, values, out))
    worst = worst_runs(rows, by, count)
    if worst:
        lines.append('worst runs' + (f' (failed, not successful, then highest {by})' if by else '') + ':')
        for row, why in worst:
            keys = ', '.join(f'{factor} {row.get(factor)}' for factor in varied)
            lines.append(f'  {row["run"]}: {why}; {keys}')
            lines.append(f'    rerun alone: {row["command"]}')
    lines.append(f'plots ({len(plots)}, histogram and ECDF of each figure) in {out}')
    return '\n'.join(lines)


def _arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('campaign', type=Path, help='campaign directory (tethersim sweep --out)')
    parser.add_argument('--out', type=Path, help='output directory (default: CAMPAIGN/report)')
    parser.add_argument('--worst', help=f'figure ranking the worst runs after the failed and unsuccessful ones '
                                        f'(default: {DEFAULT_WORST} where present)')
    parser.add_argument('--count', type=positive(int), default=5, help='worst runs listed (default 5)')


def _command(args: argparse.Namespace) -> str:
    return report(args.campaign, args.out, args.worst, args.count)


def _run(args: argparse.Namespace) -> int:
    args.out = args.out or args.campaign / 'report'
    return analysis('tethersim report campaign', _command)(args)


COMMAND = Command('a campaign (tethersim sweep): success rate with 95 %% Wilson intervals per factor level, '
                  'figure distributions, worst runs', _arguments, _run)
