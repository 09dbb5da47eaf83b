"""The `tethersim fem pendulum` command line."""

from __future__ import annotations

from pathlib import Path

import pytest

from tether_dynamics.commands import fem as fem_cli


def test_pendulum_writes_plots_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'pend'
    assert fem_cli.main(['pendulum', '--span', '0.3', '--n', '3', '--dt', '2e-4', '--out', str(out)]) == 0
    for name in ('snapshots_linear.png', 'snapshots_quadratic.png', 'energy.png', 'length.png', 'summary.txt'):
        assert (out / name).stat().st_size > 0
    text = capsys.readouterr().out
    assert 'Verdict' in text and 'quadratic' in text
    assert text == (out / 'summary.txt').read_text()


@pytest.mark.parametrize('argv', [['pendulum', '--elements', 'cubic'], ['pendulum', '--dt', '-1'],
                                  ['pendulum', '--n', 'x'], ['nosuch']])
def test_user_mistakes_exit_2_with_one_line(argv: list[str], tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'runs' / 'pendulum'
    assert fem_cli.main([*argv, '--out', str(out)] if argv != ['nosuch'] else argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith('tethersim fem: error:')
    assert not (tmp_path / 'runs').exists()
