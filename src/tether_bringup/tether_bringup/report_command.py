"""``tethersim report KIND ...``: the reports of recorded runs, one subcommand per kind.

Each package registers its reports as :class:`tether_common.command_line.Command` objects
under the ``tethersim.reports`` entry-point group (``setup.py``), named for the experiment
they report (``surrogate``, ``mission``); this command makes each a subcommand of
``tethersim report``. Only the chosen report's module is imported to run it.

Every report refuses a damaged bag (:mod:`tether_bringup.bag_reader`) unless given
``--allow-damaged``; then what it skipped of each damaged bag is added to its summary.
"""

from __future__ import annotations

import argparse
from importlib.metadata import entry_points

from tether_bringup.bag_reader import ALLOW_OPTION
from tether_bringup.bag_reader import damaged_bags_allowed
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
        report_parser.add_argument(ALLOW_OPTION, action='store_true',
                                   help='read what is intact in damaged bags and say what was skipped')
        report_parser.set_defaults(_report=report)


def _run(args: argparse.Namespace) -> int:
    with damaged_bags_allowed(args.allow_damaged) as damaged:
        status = args._report.run(args)
    return status if status else report_skipped(args, damaged)


def report_skipped(args: argparse.Namespace, damaged: list) -> int:
    """Print what was skipped of each damaged bag read and add it to ``<out>/summary.txt``; return 0."""
    lines = [line for bag in damaged for line in bag.skipped_lines()]
    if lines:
        text = '\n'.join(lines) + '\n'
        summary = args.out / 'summary.txt'
        if summary.exists():
            with open(summary, 'a', encoding='utf-8') as handle:
                handle.write(text)
        print(text, end='')
    return 0


REPORT = Command('reports computed from recorded runs: ' + ', '.join(_reports()), _arguments, _run)
