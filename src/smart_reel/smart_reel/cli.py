"""``tethersim reel``: the smart reel's analyses (gain tuning)."""

from __future__ import annotations

import argparse
import sys

from smart_reel import tuning
from tether_common.command_line import OneLineParser
from tether_common.command_line import run_analysis

PROG = 'tethersim reel'


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``tethersim reel``."""
    parser = OneLineParser(prog=PROG, description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)
    tune = sub.add_parser('tune', help='find the catenary controller gains (smart_reel.tuning)')
    tuning.add_arguments(tune)
    return parser


def _command(args: argparse.Namespace) -> str:
    return tuning.command(args)


def main(argv: list[str] | None = None) -> int:
    """Run ``tethersim reel``; return the exit status."""
    return run_analysis(PROG, build_parser(), argv, _command)


if __name__ == '__main__':
    sys.exit(main())
