"""Tests of ``tethersim catenary`` (tether_dynamics.commands.catenary)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tether_dynamics.commands import catenary as catenary_cli


def test_analyze_writes_summary_tables_and_plots(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'analyze'
    status = catenary_cli.main(['analyze', '--step', '11', '--extent', '55', '--lengths', '60',
                                '--out', str(out)])
    assert status == 0
    summary = (out / 'summary.txt').read_text(encoding='utf-8')
    for row in ('T_rob5', 'L_rob5', 'alpha_rob5', 'Recommended operating ratio', 'Δx = 20 m'):
        assert row in summary
    assert summary.strip() in capsys.readouterr().out
    assert len(list(out.glob('*.png'))) == 6


def test_reference_prints_the_envelope_comparison(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    status = catenary_cli.main(['reference', '--out', str(tmp_path)])
    assert status == 0
    printed = capsys.readouterr().out
    assert 'poly3' in printed
    assert 'max |model - exact|' in printed
    assert (tmp_path / 'fig4_3_reference_model.png').is_file()


@pytest.mark.parametrize('argv', [['analyze', '--step', '-1'], ['analyze', '--lengths', '3'],
                                  ['frobnicate'], ['analyze', '--full', '--quick']])
def test_user_mistakes_give_one_line_and_status_2(argv: list[str], tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'runs' / 'analyze'
    assert catenary_cli.main([*argv, '--out', str(out)] if argv != ['frobnicate'] else argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith('tethersim catenary: error:')
    assert '\n' not in err
    assert not (tmp_path / 'runs').exists()
