"""``tethersim reel``: user mistakes give one line and exit status 2."""

from __future__ import annotations

from smart_reel.cli import COMMAND
from tether_common.command_line import dispatch


def main(argv: list[str]) -> int:
    """``tethersim reel ARGV`` through the tethersim dispatch."""
    return dispatch('tethersim', {'reel': lambda: COMMAND}, ['reel', *argv])


def test_bad_option_is_one_line_exit_2(capsys, tmp_path):
    assert main(['tune', '--duration', '-3', '--out', str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and 'positive' in err


def test_unknown_command_is_one_line_exit_2(capsys):
    assert main(['detune']) == 2
    assert capsys.readouterr().err.startswith('tethersim reel: error: argument command: invalid choice')
