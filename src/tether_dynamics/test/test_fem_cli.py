"""The `tethersim fem pendulum` command line."""

from __future__ import annotations

from pathlib import Path

import pytest

from tether_common.command_line import dispatch
from tether_dynamics.commands import fem as fem_cli


def main(argv: list[str]) -> int:
    """``tethersim fem ARGV`` through the tethersim dispatch."""
    return dispatch('tethersim', {'fem': lambda: fem_cli.COMMAND}, ['fem', *argv])


def test_pendulum_writes_plots_and_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'pend'
    assert main(['pendulum', '--span', '0.3', '--n', '3', '--dt', '2e-4', '--out', str(out)]) == 0
    for name in ('snapshots_linear.png', 'snapshots_quadratic.png', 'energy.png', 'length.png', 'summary.txt'):
        assert (out / name).stat().st_size > 0
    text = capsys.readouterr().out
    assert text == (out / 'summary.txt').read_text()
    assert 'Neither element type peaks after 5 s' in text  # 0.3 s simulated: no late peak can exist


def test_pendulum_with_linear_elements_only_makes_no_claim_about_quadratic(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'pend'
    assert main(['pendulum', '--elements', 'linear', '--span', '0.2', '--n', '3', '--dt', '2e-4',
                         '--out', str(out)]) == 0
    text = capsys.readouterr().out
    assert 'Only linear elements were run' in text
    assert 'both element types' not in text and 'quadratic:' not in text
    assert not (out / 'snapshots_quadratic.png').exists()


@pytest.mark.parametrize('argv', [['pendulum', '--elements', 'cubic'], ['pendulum', '--dt', '-1'],
                                  ['pendulum', '--n', 'x'], ['nosuch']])
def test_user_mistakes_exit_2_with_one_line(argv: list[str], tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / 'runs' / 'pendulum'
    assert main([*argv, '--out', str(out)] if argv != ['nosuch'] else argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith('tethersim fem') and ': error: ' in err[0]
    assert not (tmp_path / 'runs').exists()
