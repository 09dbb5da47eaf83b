"""Shared pieces of the tethersim command lines: one-line errors and the analysis main loop.

A user mistake (a bad option value, an unreadable input file, an output directory that
cannot be written) is printed as one line ``<prog>: error: <what>`` with exit status 2,
never as a traceback.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path


class UsageError(Exception):
    """A user mistake: reported in one line, exit status 2."""


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors raise :class:`UsageError` instead of printing usage."""

    def error(self, message: str) -> None:
        raise UsageError(message)


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


def run_analysis(prog: str, parser: argparse.ArgumentParser, argv: list[str] | None,
                 command: Callable[[argparse.Namespace], str],
                 user_errors: tuple[type[Exception], ...] = ()) -> int:
    """Parse ``argv``, run ``command``, write its text to ``<out>/summary.txt`` and print it.

    ``args.out`` is created first; a command refused for a user mistake removes the
    directories it created while they are still empty, so bad input leaves nothing behind.
    Returns 0, or 2 after a one-line error for a :class:`UsageError`, one of
    ``user_errors`` or an OS error on the files.
    """
    created: list[Path] = []
    try:
        args = parser.parse_args(argv)
        created = [path for path in (args.out, *args.out.parents) if not path.exists()]
        args.out.mkdir(parents=True, exist_ok=True)
        text = command(args).rstrip('\n') + '\n'
        (args.out / 'summary.txt').write_text(text, encoding='utf-8')
    except (UsageError, *user_errors) as error:
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
