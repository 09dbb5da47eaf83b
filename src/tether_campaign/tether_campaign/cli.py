"""``tethersim sweep SPEC.yaml``: run a campaign (:mod:`tether_campaign.spec`) on Ray (:mod:`tether_campaign.sweep`)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from tether_bringup.errors import TethersimError
from tether_common.command_line import Command
from tether_common.command_line import positive


def _arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('spec', help='campaign spec (YAML; see docs/campaigns.md)')
    parser.add_argument('--address', help='an existing Ray cluster (e.g. HEAD:6379); default: a local Ray instance '
                                          'on this machine\'s cores, started and stopped by the command')
    parser.add_argument('--workers', type=positive(int), help='runs under way at once (default: as many as the '
                                                              'cluster\'s CPUs hold at the spec\'s cpus per run)')
    parser.add_argument('--out', type=Path, help='campaign directory (default: runs/campaign-<spec>-<time>)')
    parser.add_argument('--resume', action='store_true', help='run only the runs the campaign directory has no '
                                                              'record of (after an interrupted campaign)')
    parser.add_argument('--keep', choices=('all', 'failed'), default='all',
                        help='run directories to keep whole: all (default), or only the failed runs\' (the others '
                             'keep their scene, figures, summary and log)')
    parser.add_argument('--retries', type=int, choices=range(0, 11), metavar='N',
                        help='tries again of a failed run, 0-10 (default: the spec\'s retries, else 2)')


def _run(args: argparse.Namespace) -> int:
    from tether_campaign.spec import load_campaign
    from tether_campaign.sweep import SweepOptions
    from tether_campaign.sweep import sweep

    campaign = load_campaign(args.spec)
    out = args.out or Path('runs') / f'campaign-{campaign.name}-{time.strftime("%Y%m%d-%H%M%S")}'
    return sweep(campaign, SweepOptions(out=out, address=args.address, workers=args.workers, resume=args.resume,
                                        keep=args.keep, retries=args.retries))


SWEEP = Command('run a campaign: a scene over grids and seeded draws of its parameters, as Ray tasks',
                _arguments, _run, (TethersimError,))
