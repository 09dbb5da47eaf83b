"""``tethersim report KIND ...``: the reports of recorded runs, one subcommand per kind.

Each package registers its reports as :class:`tether_common.command_line.Command` objects
under the ``tethersim.reports`` entry-point group (``setup.py``), named for the experiment
they report (``surrogate``, ``mission``); this command makes each a subcommand of
``tethersim report``. Only the chosen report's module is imported to run it.
"""

from __future__ import annotations

import argparse
from importlib.metadata import entry_points

from tether_common.command_line import Command
from tether_common.command_line import OneLineParser

REPORT_GROUP = 'tethersim.reports'


def _reports() -> dict:
    return {entry.name: entry for entry in sorted(entry_points(group=REPORT_GROUP), key=lambda e: e.name)}


def _arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='report', required=True, parser_class=OneLineParser, metavar='KIND')
    for name, entry in _reports().items():
        report = entry.load()
        report_parser = sub.add_parser(name, help=report.help, description=report.help)
        report.add_arguments(report_parser)
        report_parser.set_defaults(_report=report)


def _run(args: argparse.Namespace) -> int:
    return args._report.run(args)


REPORT = Command('reports computed from recorded runs: ' + ', '.join(_reports()), _arguments, _run)
