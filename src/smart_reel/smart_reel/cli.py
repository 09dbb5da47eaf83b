"""``tethersim reel``: the smart reel's analyses (gain tuning)."""

from __future__ import annotations

import argparse

from smart_reel import tuning
from tether_common.command_line import Command
from tether_common.command_line import OneLineParser
from tether_common.command_line import analysis

PROG = 'tethersim reel'


def _arguments(parser: argparse.ArgumentParser) -> None:
    """Add the subcommands of ``tethersim reel`` to its parser."""
    sub = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)
    tune = sub.add_parser('tune', help='find the catenary controller gains (smart_reel.tuning)')
    tuning.add_arguments(tune)


def _command(args: argparse.Namespace) -> str:
    return tuning.command(args)


COMMAND = Command('smart reel: catenary-controller gain tuning (Sec. 4.2)', _arguments, analysis(PROG, _command))
