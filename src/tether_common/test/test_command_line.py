"""The tethersim dispatch: one parser from the registered commands, one-line errors, load failures as themselves."""

from __future__ import annotations

import argparse
import subprocess
import sys

from tether_common.command_line import Command
from tether_common.command_line import UsageError
from tether_common.command_line import dispatch
from tether_common.command_line import installed_commands


def _echo_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--times', type=int, required=True)


def _echo(args: argparse.Namespace) -> int:
    if args.times < 0:
        raise UsageError(f'--times must not be negative, got {args.times}')
    print('echo ' * args.times)
    return 7


ECHO = Command('repeat a word', _echo_arguments, _echo)


def _broken() -> Command:
    import tether_common.no_such_module  # noqa: F401 - the import error under test
    return ECHO


def test_the_chosen_command_runs_and_only_it_is_loaded(capsys):
    assert dispatch('prog', {'echo': lambda: ECHO, 'broken': _broken}, ['echo', '--times', '2']) == 7
    assert capsys.readouterr().out == 'echo echo \n'


def test_an_import_error_in_a_command_module_is_reported_as_that_error(capsys):
    assert dispatch('prog', {'echo': lambda: ECHO, 'broken': _broken}, ['broken']) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("prog: error: the broken command cannot be loaded: ModuleNotFoundError: "
                             "No module named 'tether_common.no_such_module' (")
    assert 'test_command_line.py' in err[0]


def test_user_mistakes_give_one_line_and_status_2(capsys):
    assert dispatch('prog', {'echo': lambda: ECHO}, ['echo', '--times', 'x']) == 2
    assert capsys.readouterr().err.strip() == "prog echo: error: argument --times: invalid int value: 'x'"
    assert dispatch('prog', {'echo': lambda: ECHO}, ['echo', '--times', '-1']) == 2
    assert capsys.readouterr().err.strip() == 'prog: error: --times must not be negative, got -1'
    assert dispatch('prog', {'echo': lambda: ECHO}, ['nosuch']) == 2
    assert capsys.readouterr().err.strip().startswith("prog: error: argument COMMAND: invalid choice: 'nosuch'")


def test_every_package_registers_its_commands():
    assert {'run', 'replay', 'scenes', 'bag', 'catenary', 'fem', 'psr', 'reel', 'report'} <= set(installed_commands())
    assert all(isinstance(load(), Command) for load in installed_commands().values())


def test_python_m_tether_bringup_is_the_tethersim_program():
    result = subprocess.run([sys.executable, '-m', 'tether_bringup', '--help'], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    listed = {line.split()[0] for line in result.stdout.splitlines() if line.startswith('    ') and line.split()}
    assert set(installed_commands()) <= listed
