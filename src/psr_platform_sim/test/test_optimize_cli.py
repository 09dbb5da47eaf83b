"""Design study (Sec. 2.5) on a small grid, and the `tethersim psr` command line."""

from __future__ import annotations

import numpy as np

from psr_platform_sim.cli import COMMAND
from psr_platform_sim.kinematics import Design
from psr_platform_sim.optimize import StudySettings
from psr_platform_sim.optimize import run_study
from psr_platform_sim.workspace import ball_region
from psr_platform_sim.workspace import cached_table
from psr_platform_sim.workspace import nominal_region
from tether_common.command_line import dispatch


def main(argv: list[str]) -> int:
    """``tethersim psr ARGV`` through the tethersim dispatch."""
    return dispatch('tethersim', {'psr': lambda: COMMAND}, ['psr', *argv])


def test_small_study_ranks_designs_and_reports_progress():
    settings = StudySettings(ratio_low=0.95, ratio_high=1.05, ratio_step=0.05, slider_steps=80,
                             gamma_low_deg=28.0, gamma_high_deg=32.0)
    calls = []
    result = run_study(settings, lambda done, total, elapsed: calls.append((done, total)))
    assert calls[-1] == (9, 9) and len(calls) == 9
    top = result.top_nominal(3)
    areas = [row[0] for row in top]
    assert areas == sorted(areas, reverse=True) and areas[0] > 4000.0
    best = result.top_ball(1)[0]
    assert 2000.0 < best[0] < 3200.0 and 28.0 <= best[3] <= 32.0
    assert settings.solves == 9 * 80**2


def test_full_study_grid_is_the_thesis_grid():
    settings = StudySettings()
    assert settings.ratios.size == 41 and settings.ratios[0] == 0.5 and settings.ratios[-1] == 1.5
    assert settings.gammas_deg.size == 26
    assert settings.solves == 41 * 41 * 200 * 200  # ~67 million, "~70 million" in Sec. 2.5.2


def test_cli_bad_arguments_exit_2_with_one_line(tmp_path, capsys):
    assert main(['optimize', '--fraction', '2', '--out', str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith('tethersim psr: error: --fraction') and '\n' not in err
    assert main(['workspace', '--l', '-1', '--out', str(tmp_path)]) == 2


def test_cli_workspace_writes_plots_and_summary(tmp_path, capsys):
    out = tmp_path / 'ws'
    assert main(['workspace', '--l', '0.975', '--d', '1.15', '--gamma', '25', '--steps', '60', '--out', str(out),
                 '--cache', str(tmp_path / 'cache')]) == 0
    summary = (out / 'summary.txt').read_text()
    assert summary == capsys.readouterr().out
    table = cached_table(Design(1.0, 0.975, 1.15, np.radians(25.0)), 60, tmp_path / 'cache')
    assert f'usable (Eq. 2.16, no kinematic lock): {nominal_region(table).area:.1f} deg2' in summary
    assert f'with ball-joint limit, gamma=25 deg: {ball_region(table).area:.1f} deg2' in summary
    assert ball_region(table).area != ball_region(table, np.radians(30.0)).area
    assert (out / 'workspace.png').stat().st_size > 20_000
    assert (out / 'workspace_ball.png').stat().st_size > 20_000


def test_cli_optimize_fraction_extrapolates(tmp_path, capsys):
    out = tmp_path / 'opt'
    assert main(['optimize', '--quick', '--fraction', '0.1', '--out', str(out), '--cache', str(tmp_path / 'c')]) == 0
    summary = capsys.readouterr().out
    assert 'fraction run: 2/21 arm lengths; extrapolated full study' in summary
    study = np.load(out / 'study.npz')
    assert study['nominal_area'].shape == (21, 21)
    rank_1 = summary.splitlines()[summary.splitlines().index(' rank   area deg2    l      d   |  area deg2    l      d') + 1]
    best = np.where(study['components'] == 1, study['nominal_area'], -1.0).max()
    assert rank_1.split()[:2] == ['1', f'{best:.1f}']
    for name in ('study_area.png', 'optimized_workspace.png', 'workspace_best.png'):
        assert (out / name).stat().st_size > 20_000
