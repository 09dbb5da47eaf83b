"""The ``tethersim`` program and the bringup's commands: run, replay, scenes, bag.

Every subcommand, these and the analysis groups of other packages, is a
:class:`tether_common.command_line.Command` registered under the ``tethersim.commands``
entry-point group of its package's ``setup.py``; :func:`main` dispatches among the
installed ones (``python -m tether_bringup`` runs it too).
"""

from __future__ import annotations

import argparse
import errno
import socket
import sys
import time
from pathlib import Path

from tether_bringup.errors import TethersimError
from tether_bringup.recorder_params import LIVE_HOST
from tether_bringup.recorder_params import LIVE_PORT
from tether_bringup.sim_clock import MAX_RATE
from tether_common.command_line import Command
from tether_common.command_line import OneLineParser
from tether_common.command_line import UsageError
from tether_common.command_line import dispatch
from tether_common.command_line import installed_commands
from tether_common.command_line import positive

DESCRIPTION = 'Tethered UAV over a USV with a smart reel, as a ROS 2 node graph.'


def _domain(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f'expected an integer, got {text!r}') from None
    if value == 0:
        raise argparse.ArgumentTypeError('expected a ROS domain id in [1, 232], got 0: ROS\'s default domain, which '
                                         'every ROS 2 process on the network that sets none joins')
    if not 1 <= value <= 232:
        raise argparse.ArgumentTypeError(f'expected a ROS domain id in [1, 232], got {value}')
    return value


def _rate(text: str) -> float:
    return MAX_RATE if text == 'max' else positive()(text)


def _add_network(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--domain-id', type=_domain, default=None,
                        help='ROS_DOMAIN_ID of the run, 1-232 (default: a private one in 1-100 reserved for the run; '
                             '0, the domain of every ROS 2 process that sets none, is refused)')
    parser.add_argument('--discovery', choices=('localhost', 'subnet'), default='localhost',
                        help='DDS discovery range: localhost (default) or subnet to span machines')


def _port(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f'expected a TCP port, got {text!r} (give the scene before --live)') from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f'expected a TCP port in [0, 65535] (0: any free one), got {value}')
    return value


def _add_live(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--live', nargs='?', type=_port, const=LIVE_PORT, metavar='PORT',
                        help=f'serve the recorded topics over the Foxglove WebSocket protocol while it runs, on '
                             f'ws://HOST:PORT (default port {LIVE_PORT}; 0: any free one; see docs/live.md)')
    parser.add_argument('--live-wait', action='store_true',
                        help='with --live: start the clock only once a client has subscribed (watch from the start)')
    parser.add_argument('--live-host', default=LIVE_HOST, metavar='HOST',
                        help=f'address the live server listens on (default {LIVE_HOST}, this machine only)')


def _live(args: argparse.Namespace) -> tuple[str, int] | None:
    """The live server's (host, port), or None without --live; a port another program holds is a usage error."""
    if args.live is None:
        if args.live_host != LIVE_HOST or args.live_wait:
            raise UsageError(f'{"--live-wait" if args.live_wait else "--live-host"} without --live: add --live [PORT]')
        return None
    if args.live:
        try:
            with socket.socket(socket.AF_INET6 if ':' in args.live_host else socket.AF_INET) as probe:
                probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as the server's own listener
                probe.bind((args.live_host, args.live))
        except OSError as error:
            fix = 'give another port (--live PORT)' if error.errno == errno.EADDRINUSE else \
                'give an address of this machine (--live-host)'
            raise UsageError(f'--live: cannot listen on {args.live_host}:{args.live} ({error.strerror}); {fix}') \
                from None
    return args.live_host, args.live


def _run_arguments(run: argparse.ArgumentParser) -> None:
    run.add_argument('scene', nargs='?', default='default', help='scene name (see `tethersim scenes`) or YAML file')
    run.add_argument('--duration', type=positive(), help='sim time to run, s (default: the scene\'s)')
    run.add_argument('--rate', type=_rate, help='real-time factor, or max: as fast as the slowest node (default: the scene\'s)')
    run.add_argument('--out', type=Path, help='run directory (default: runs/<scene>-<time>)')
    _add_live(run)
    _add_network(run)


def _replay_arguments(replay: argparse.ArgumentParser) -> None:
    replay.add_argument('bag', help='bag file, bag directory or run directory')
    replay.add_argument('--topics', nargs='+', help='replay only these topics')
    replay.add_argument('--rate', type=_rate, default=1.0, help='real-time factor, or max (default 1)')
    replay.add_argument('--scene', help='also run the nodes of this scene (e.g. an estimator under test)')
    replay.add_argument('--clock-step', type=positive(), default=0.01, help='s of bag time between /clock ticks')
    replay.add_argument('--out', type=Path, help='run directory (default: runs/replay-<time>)')
    _add_live(replay)
    _add_allow_damaged(replay)
    _add_network(replay)


def _add_allow_damaged(parser: argparse.ArgumentParser) -> None:
    from tether_bringup.bag_reader import ALLOW_OPTION
    parser.add_argument(ALLOW_OPTION, action='store_true',
                        help='read what is intact in a damaged bag (chunks failing their CRC check skipped, and said '
                             'so) instead of refusing it')


def _bag_arguments(bag: argparse.ArgumentParser) -> None:
    bag_commands = bag.add_subparsers(dest='bag_command', required=True, parser_class=OneLineParser)
    info = bag_commands.add_parser('info', help='topics, types, counts, rates, duration, damage')
    info.add_argument('bag')
    info.add_argument('--check', action='store_true',
                      help='also decode every message; list every damaged place; exit 2 if the bag is damaged')
    export = bag_commands.add_parser('export', help='one topic as CSV, one row per message')
    export.add_argument('bag')
    export.add_argument('--topic', required=True)
    export.add_argument('--csv', required=True, type=Path)
    _add_allow_damaged(export)
    recover = bag_commands.add_parser('recover', help='rewrite a damaged or unfinalized bag as a finalized one')
    recover.add_argument('bag')


def _default_out(name: str) -> Path:
    return Path('runs') / f'{name}-{time.strftime("%Y%m%d-%H%M%S")}'


def _run(args: argparse.Namespace) -> int:
    from tether_bringup.bringup import RunOptions
    from tether_bringup.bringup import execute
    from tether_bringup.environment import reserved_domain
    from tether_bringup.scene import find_scene
    from tether_bringup.scene import load_scene
    from tether_bringup.time_sources import PacedClock

    scene = load_scene(find_scene(args.scene))
    duration = args.duration or scene.duration
    rate = args.rate or scene.rate
    _check_pace(scene.nodes, rate)
    source = PacedClock(duration, scene.clock_step, rate)
    with reserved_domain(args.domain_id) as domain_id:
        options = RunOptions(out_dir=args.out or _default_out(scene.name), domain_id=domain_id,
                             discovery=args.discovery, exclude=tuple(scene.exclude), reports=tuple(scene.reports),
                             title=f'tethersim run {scene.name}', lockstep_window=scene.lockstep_window,
                             compose=scene.compose, live=_live(args), live_wait=args.live_wait)
        return execute(scene.nodes, source, options)


def _check_pace(nodes, rate: float) -> None:
    """Refuse a real-time factor a node on its own clock cannot follow: its parameters module's
    ``pace_problem(parameters, rate)`` (the sitl node's SITL at a fixed speed-up) says why.
    """
    from tether_bringup.errors import SceneError
    from tether_common.parameters import parameter_module
    for config in nodes:
        module = parameter_module(config.package, config.executable) if config.package else None
        if module is None:
            continue
        problem = getattr(module, 'pace_problem', lambda parameters, rate: None)(config.parameters, rate)
        if problem:
            raise SceneError(f'node {config.name}: {problem}')


def _replay(args: argparse.Namespace) -> int:
    from tether_bringup.bag_reader import read_bag
    from tether_bringup.bag_reader import ALLOW_OPTION
    from tether_bringup.bringup import RunOptions
    from tether_bringup.bringup import execute
    from tether_bringup.environment import reserved_domain
    from tether_bringup.errors import BagError
    from tether_bringup.recorder_params import DEFAULT_EXCLUDE
    from tether_bringup.scene import find_scene
    from tether_bringup.scene import load_scene
    from tether_bringup.time_sources import BagPlayback

    bag = read_bag(args.bag, allow_damaged=args.allow_damaged)
    missing = [t for t in args.topics or [] if t not in bag.topics]
    if missing:
        raise BagError(f'{bag.path}: no messages on {", ".join(missing)} (topics: {", ".join(sorted(bag.topics))})')
    chosen = set(args.topics or bag.topics) - {'/clock'}
    topics = {name: (t.type_name, t.qos) for name, t in bag.topics.items() if name in chosen}
    messages = [m for m in bag.messages if m.topic in chosen]
    if not messages:
        raise BagError(f'{bag.path}: nothing to replay' + (f' (damaged at {bag.damage_line()})' if bag.damage else ''))
    if bag.damage:
        print(f'tethersim: warning: {bag.path} is damaged at {bag.damage_line()}; replaying its '
              f'{len(messages)} intact messages ({ALLOW_OPTION})', file=sys.stderr, flush=True)
    nodes, exclude, reports, name, compose = [], list(DEFAULT_EXCLUDE), [], 'replay', True
    if args.scene:
        scene = load_scene(find_scene(args.scene))
        nodes, exclude, reports, name = scene.nodes, scene.exclude, scene.reports, f'replay-{scene.name}'
        compose = scene.compose
    source = BagPlayback(messages, topics, args.clock_step, args.rate)
    with reserved_domain(args.domain_id) as domain_id:
        options = RunOptions(out_dir=args.out or _default_out(name), domain_id=domain_id,
                             discovery=args.discovery, exclude=tuple(exclude), reports=tuple(reports),
                             title=f'tethersim replay {bag.path.name}', compose=compose, live=_live(args),
                             live_wait=args.live_wait)
        return execute(nodes, source, options)


def _scenes(args: argparse.Namespace) -> int:
    from tether_bringup.scene import list_scenes
    entries = list_scenes()
    width = max((len(name) for name, _ in entries), default=0)
    for name, description in entries:
        print(f'{name:<{width}}  {description}')
    return 0


def _bag(args: argparse.Namespace) -> int:
    from tether_bringup.bag_info import describe_bag
    from tether_bringup.bag_info import export_csv
    from tether_bringup.bag_info import read_for_info
    from tether_bringup.bag_reader import damaged_bags_allowed
    if args.bag_command == 'info':
        bag = read_for_info(args.bag, check=args.check)
        print('\n'.join(describe_bag(bag, check=args.check)))
        if args.check and bag.damage:
            print(f'tethersim bag info: error: {bag.path} is damaged at {bag.damage_line()}', file=sys.stderr)
            return 2
        return 0
    if args.bag_command == 'recover':
        from tether_bringup.bag_recover import recover_bag
        from tether_bringup.bag_reader import resolve_bag
        recovery = recover_bag(args.bag)
        print(recovery.line() if recovery else f'{resolve_bag(args.bag)}: finalized and undamaged; nothing to recover')
        return 0
    with damaged_bags_allowed(args.allow_damaged) as damaged:
        rows = export_csv(args.bag, args.topic, args.csv)
    print(f'wrote {rows} rows of {args.topic} to {args.csv}')
    for bag in damaged:
        print('\n'.join(bag.skipped_lines()))
    return 0


RUN = Command('run a scene and record it', _run_arguments, _run, (TethersimError,))
REPLAY = Command('republish a bag with /clock from it, recording a new bag', _replay_arguments, _replay,
                 (TethersimError,))
SCENES = Command('list the installed scenes', lambda parser: None, _scenes, (TethersimError,))
BAG = Command('inspect, export and recover bags', _bag_arguments, _bag, (TethersimError,))


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``tethersim`` command; returns the exit status."""
    return dispatch('tethersim', installed_commands(), sys.argv[1:] if argv is None else argv, DESCRIPTION)


if __name__ == '__main__':
    sys.exit(main())
