"""The tethersim command line: its subcommands, one-line errors and the analysis main loop.

Every ``tethersim`` subcommand is a :class:`Command` that its package registers under the
``tethersim.commands`` entry-point group (``setup.py``); :func:`dispatch` builds one parser
from them and runs the chosen one, importing only that command's module. A user mistake (a
bad option value, an unreadable input file, an output directory that cannot be written) is
printed as one line ``<prog>: error: <what>`` with exit status 2, never as a traceback (a
mistake in the arguments names the (sub)command they belong to, as argparse does); a command
module that fails to import is reported as that import error (exit 1).
"""

from __future__ import annotations

import argparse
import math
import sys
import traceback
from collections.abc import Callable
from collections.abc import Mapping
from dataclasses import dataclass
from importlib.metadata import entry_points

COMMAND_GROUP = 'tethersim.commands'


class UsageError(Exception):
    """A user mistake: reported in one line, exit status 2; ``prog`` names the command that found it."""

    def __init__(self, message: str, prog: str | None = None) -> None:
        super().__init__(message)
        self.prog = prog


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors raise :class:`UsageError` instead of printing usage."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message, self.prog)


@dataclass(frozen=True)
class Command:
    """One ``tethersim`` subcommand.

    Attributes:
        help: one line for ``tethersim --help``.
        add_arguments: adds the command's arguments (and its own subcommands) to its parser.
        run: does the work for the parsed arguments; returns the exit status.
        user_errors: exceptions that are user mistakes, printed in one line with status 2.
    """

    help: str
    add_arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]
    user_errors: tuple[type[Exception], ...] = ()


def installed_commands() -> dict[str, Callable[[], Command]]:
    """The commands of every installed package, by name, as loaders (nothing is imported yet)."""
    return {entry.name: entry.load for entry in sorted(entry_points(group=COMMAND_GROUP), key=lambda e: e.name)}


class CommandLoadError(Exception):
    """A command's module raised while it was imported (a broken installation, not a user mistake)."""


def _load(name: str, loader: Callable[[], Command]) -> Command:
    try:
        command = loader()
    except Exception as error:  # whatever the module raised on import is the message
        frame = traceback.extract_tb(error.__traceback__)[-1]
        raise CommandLoadError(f'the {name} command cannot be loaded: {type(error).__name__}: {error} '
                               f'({frame.filename}:{frame.lineno})') from None
    if not isinstance(command, Command):
        raise CommandLoadError(f'the {name} command is registered as {type(command).__name__}, not a Command')
    return command


def dispatch(prog: str, commands: Mapping[str, Callable[[], Command]], argv: list[str],
             description: str = '') -> int:
    """Parse ``argv`` against ``commands`` and run the chosen one; return the exit status.

    Only the chosen command's module is imported; all are for ``--help`` or a missing or
    unknown command name.
    """
    chosen = argv[0] if argv and argv[0] in commands else None
    parser = OneLineParser(prog=prog, description=description)
    sub = parser.add_subparsers(dest='tethersim_command', required=True, parser_class=OneLineParser,
                                metavar='COMMAND')
    try:
        for name, loader in commands.items():
            if chosen is not None and name != chosen:
                continue
            command = _load(name, loader)
            command_parser = sub.add_parser(name, help=command.help, description=command.help)
            command.add_arguments(command_parser)
            command_parser.set_defaults(_command=command)
    except CommandLoadError as error:
        print(f'{prog}: error: {error}', file=sys.stderr)
        return 1
    try:
        args = parser.parse_args(argv)
    except UsageError as error:
        print(f'{error.prog or prog}: error: {error}', file=sys.stderr)
        return 2
    command = args._command
    user_errors: tuple[type[Exception], ...] = (UsageError, *command.user_errors)
    try:
        return command.run(args)
    except user_errors as error:
        print(f'{getattr(error, "prog", None) or prog}: error: {error}', file=sys.stderr)
        return 2


def positive(kind: type = float) -> Callable[[str], float]:
    """Return an argparse type that accepts a finite positive ``kind`` (float or int)."""
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f'expected a number, got {text!r}') from None
        if not value > 0 or not math.isfinite(value):
            raise argparse.ArgumentTypeError(f'expected a positive number, got {text!r}')
        return value
    return parse


def analysis(prog: str, command: Callable[[argparse.Namespace], str],
             user_errors: tuple[type[Exception], ...] = ()) -> Callable[[argparse.Namespace], int]:
    """Return the ``run`` of an analysis command: ``command`` writes plots into ``args.out`` and returns its text.

    ``args.out`` is created first; the text is written to ``<out>/summary.txt`` and printed. A
    command refused for a user mistake removes the directories it created while they are still
    empty, so bad input leaves nothing behind. Returns 0, or 2 after a one-line error for a
    :class:`UsageError`, one of ``user_errors`` or an OS error on the files.
    """
    mistakes: tuple[type[Exception], ...] = (UsageError, *user_errors)

    def run(args: argparse.Namespace) -> int:
        created = [path for path in (args.out, *args.out.parents) if not path.exists()]
        try:
            args.out.mkdir(parents=True, exist_ok=True)
            text = command(args).rstrip('\n') + '\n'
            (args.out / 'summary.txt').write_text(text, encoding='utf-8')
        except mistakes as error:
            for path in created:
                if path.is_dir() and not any(path.iterdir()):
                    path.rmdir()
            print(f'{prog}: error: {error}', file=sys.stderr)
            return 2
        except OSError as error:
            where = f'{error.filename}: ' if error.filename else ''
            print(f'{prog}: error: {where}{error.strerror or error}', file=sys.stderr)
            return 2
        print(text, end='')
        return 0
    return run
