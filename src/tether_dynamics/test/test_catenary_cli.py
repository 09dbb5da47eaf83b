"""Tests of ``tethersim catenary`` (tether_dynamics.commands.catenary)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tether_common.command_line import dispatch
from tether_dynamics.commands import catenary as catenary_cli
from tether_dynamics.statics import flying_space
from tether_dynamics.statics import heave_robustness


def main(argv: list[str]) -> int:
    """``tethersim catenary ARGV`` through the tethersim dispatch."""
    return dispatch('tethersim', {'catenary': lambda: catenary_cli.COMMAND}, ['catenary', *argv])


def test_analyze_writes_summary_tables_and_plots(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'analyze'
    status = main(['analyze', '--step', '11', '--extent', '55', '--lengths', '60',
                                '--out', str(out)])
    assert status == 0
    summary = (out / 'summary.txt').read_text(encoding='utf-8')
    assert summary.strip() in capsys.readouterr().out
    best_ratio, best_heave = flying_space.recommended_ratio(0.05)
    assert f'Δx/Δy = {best_ratio:.3f}, tolerance {best_heave:.5f}·Δy' in summary
    heave_10 = heave_robustness.robust_length(20.0, 55.0, 0.10).heave
    assert f'this model gives {heave_10:.3f} m at 10 %' in summary
    assert len(list(out.glob('*.png'))) == 6


def test_reference_prints_the_envelope_comparison(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    status = main(['reference', '--out', str(tmp_path)])
    assert status == 0
    printed = capsys.readouterr().out
    _, error = catenary_cli.envelope_report(np.linspace(2.0, 60.0, 59), np.linspace(0.0, 2.0, 201))
    assert f'overall: max |model - exact| = {np.abs(error).max():.4f} m' in printed
    assert (tmp_path / 'fig4_3_reference_model.png').is_file()


@pytest.mark.parametrize('argv', [['analyze', '--step', '-1'], ['analyze', '--lengths', '3'],
                                  ['frobnicate'], ['analyze', '--full', '--quick']])
def test_user_mistakes_give_one_line_and_status_2(argv: list[str], tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'runs' / 'analyze'
    assert main([*argv, '--out', str(out)] if argv != ['frobnicate'] else argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith('tethersim catenary') and ': error: ' in err
    assert '\n' not in err
    assert not (tmp_path / 'runs').exists()


def test_ratio_sentence_follows_the_tolerance_lost_at_the_thesis_ratio() -> None:
    flat = catenary_cli._ratio_sentence(0.45, 0.30, 0.2999)
    assert 'Δx/Δy = 0.450' in flat and '0.03 % less' in flat and 'the maximum is flat' in flat
    steep = catenary_cli._ratio_sentence(0.60, 0.30, 0.25)
    assert 'difference +0.140' in steep and '16.67 % less' in steep
    assert 'gives up a measurable part' in steep and 'flat' not in steep


def test_heave_sentence_compares_the_10_percent_rise_with_the_thesis() -> None:
    assert catenary_cli._heave_sentence([0.5, 0.8, 1.0]).endswith('this model gives 0.800 m at 10 %, +0.050 m from it')
    assert catenary_cli._heave_sentence([0.2, 0.3, 0.4]).endswith('this model gives 0.300 m at 10 %, -0.450 m from it')
