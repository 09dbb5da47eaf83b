"""Graph throughput: real-time factor and CPU per message per node as nodes and topics are added.

Each stage is a scene run with ``tethersim run --rate max`` (lockstep: as fast as the
slowest process allows), once per configuration in the same benchmark run:

* ``before``: rclpy's default ``SingleThreadedExecutor`` in every process
  (``TETHERSIM_EXECUTOR=single``), ``/clock`` every 10 ms, each step waiting for every ack;
* ``events``: the ``EventsExecutor`` the nodes use, same clock;
* ``after``: ``EventsExecutor``, ``/clock`` every 50 ms (``clock_step``) and a 50 ms
  ``lockstep_window``: the nodes still tick at their own rates;
* ``group``: as ``after``, and the nodes whose packages register their class run in one
  process, the node group (``tether_bringup.node_group``), as the scenes run them; the
  others (the load nodes, scripts) and the recorder in their own.

Stages:

1. ``platform``: the platform node (4 topics at 100 Hz) and the recorder;
2. ``+ plant``: the tether plant of ``tether_demo`` (quasi-static, 3 topics at 100 Hz, 2 at 10 Hz);
3. ``+ reel``: the smart reel node on /tether/state and /truth/relative (1 topic at 100 Hz, 2 at 50 Hz);
4. ``+ load``: two load nodes (``load_node.py``, 3 Imu topics at 100 Hz each) standing in for
   the sensor, estimator and UAV nodes;
5. ``scene NAME`` (``--scene``, default the fullest installed scene): that scene's nodes and
   parameters as they are;
6. ``NAME quadratic``: the same with the plant on quadratic elements at N = 20 (0.1 ms steps),
   the graph the throughput goal is set for (at least 5x real time in the node group on this
   2-core machine); the last lines say whether this run met it, and how the machine's cores
   were shared meanwhile (the run summary's ``/proc/stat`` line: this run, other processes,
   idle, stolen by the hypervisor).

Per process it reports CPU seconds from the first tick to the last ack (the run summary's
``cpu s/sim s``: start-up and shutdown excluded), messages handled counted from the
bag and the run's ``graph.yaml``: published plus taken (each topic it subscribes to; for a
lockstep node also both ``/clock`` subscriptions and one ack per ``/clock``; every recorded
message and one ack per ``/clock`` for the recorder; ``/clock`` and the acks for the time
master ``tethersim``; the node group's, those of its nodes added up), CPU per message and CPU
per simulated second; per stage the achieved real-time factor and the CPU-bound ceiling the
run summary prints (cores / total CPU per simulated second, and no more than one core for a
process's main thread, the one that runs Python: 1 / the busiest main thread's CPU per
simulated second), which does not depend on what else loads the machine. Writes
``summary.txt`` and ``table.csv`` to --out.

Last, the live view: the scene stage in the ``group`` configuration again with ``--live``
and a client subscribed to every topic, decoding each message (``test/live_client``,
Foxglove's own protocol client under Node.js, ``make live-client``; skipped without it).
It reports the live server's CPU per simulated second (its thread and the Foxglove SDK's,
the run's ``live.yaml``) against the node group's (goal: at most
:data:`LIVE_GOAL` of it), and the recorder's with and without the server.

Run:  ./tethersim-env python bench/graph_throughput/run.py [--duration 10] [--scene NAME] [--out DIR] [--live-only]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import yaml

from tether_bringup.bag_reader import read_bag
from tether_bringup.errors import SceneError
from tether_bringup.live_server import cpu_per_sim_second
from tether_bringup.node_group import GROUP_NAME
from tether_bringup.scene import find_scene

HERE = Path(__file__).resolve().parent
FULLEST_SCENES = ('outdoor_flight', 'tether_demo')
"""Scenes the last stage runs by default: the first one installed (the fullest graph first)."""
CONFIGS = {
    'before': {'executor': 'single', 'clock_step': 0.01, 'lockstep_window': 0.0, 'compose': False},
    'events': {'executor': 'events', 'clock_step': 0.01, 'lockstep_window': 0.0, 'compose': False},
    'after': {'executor': 'events', 'clock_step': 0.05, 'lockstep_window': 0.05, 'compose': False},
    'group': {'executor': 'events', 'clock_step': 0.05, 'lockstep_window': 0.05, 'compose': True},
}
PLATFORM = {'package': 'psr_platform_sim', 'executable': 'platform',
            'parameters': {'profile': 'hpr1', 'seed': 1, 'profile_duration': 60.0}}
PLANT = {'package': 'tether_dynamics', 'executable': 'plant',
         'parameters': {'fidelity': 'quasi_static', 'integration_step': 0.01, 'state_rate': 100.0,
                        'nodes_rate': 10.0, 'markers_rate': 10.0, 'reel_input': 'reference',
                        'uav_source': 'fixed', 'uav_position': [3.22, 0.0, 5.9]}}
REEL = {'package': 'smart_reel', 'executable': 'reel', 'parameters': {'relative_source': 'truth'}}
GOAL = 5.0
"""Real-time factor the full graph with the quadratic plant is to reach in the node group."""
LIVE_GOAL = 0.10
"""The live server's CPU per simulated second as a share of the node group's it is to stay within."""
LIVE_CLIENT = HERE.parent.parent / 'test' / 'live_client'
LIVE_MISSING = 'live view: not measured (needs Node.js and `make live-client`)'
QUADRATIC = {'fidelity': 'quadratic', 'elements': 20, 'integration_step': 1e-4}
STAGES = {
    'platform': {'platform': PLATFORM},
    '+ plant': {'platform': PLATFORM, 'plant': PLANT},
    '+ reel': {'platform': PLATFORM, 'plant': PLANT, 'reel': REEL},
    '+ load': {'platform': PLATFORM, 'plant': PLANT, 'reel': REEL,
               'load_a': {'script': str(HERE / 'load_node.py'), 'parameters': {'topics': 3}},
               'load_b': {'script': str(HERE / 'load_node.py'), 'parameters': {'topics': 3}}},
}


@dataclass
class NodeRow:
    stage: str
    config: str
    node: str
    cpu_per_sim_second: float
    """CPU s per simulated s from the first tick to the last ack (the run summary's ``cpu s/sim s``)."""
    messages: int
    sim_time: float

    @property
    def cpu(self) -> float:
        """CPU s over the simulated time, start-up and shutdown excluded."""
        return self.cpu_per_sim_second * self.sim_time

    @property
    def us_per_message(self) -> float:
        return self.cpu / self.messages * 1e6 if self.messages else float('nan')


def _scene(path: Path, nodes: dict, duration: float, config: dict) -> None:
    path.write_text(yaml.safe_dump({'description': 'graph throughput stage', 'duration': duration,
                                    'rate': 'max', 'clock_step': config['clock_step'],
                                    'lockstep_window': config['lockstep_window'], 'compose': config['compose'],
                                    'nodes': nodes}, sort_keys=False))


def scene_nodes(name: str) -> dict:
    """The nodes of an installed scene (or scene file), script paths made absolute."""
    path = find_scene(name)
    nodes = yaml.safe_load(path.read_text())['nodes']
    for settings in nodes.values():
        if 'script' in settings:
            settings['script'] = str((path.parent / settings['script']).resolve())
    return nodes


def _summary(run_dir: Path) -> tuple[float, float, float, dict[str, float]]:
    """Achieved real-time factor, simulated time, the CPU-bound ceiling and CPU s per simulated s of each
    process from summary.txt (the node group's own row, not the rows of its nodes under it).
    """
    lines = (run_dir / 'summary.txt').read_text().splitlines()
    rate = sim = ceiling = None
    cpu = {}
    in_table = False
    for line in lines:
        if 'achieved real-time factor' in line:
            sim = float(line.split('simulated ')[1].split(' s')[0])
            rate = float(line.split('achieved real-time factor ')[1].split()[0])
        elif line.startswith('cpu s/sim s:'):
            ceiling = float(line.rpartition('ceiling ')[2].rstrip('x'))
        elif line.startswith('node '):
            in_table = True
        elif in_table and line.startswith('total'):
            in_table = False
        elif in_table and len(line.split()) == 5:
            name, _, _, per_sim_second, _ = line.split()
            cpu[name] = float(per_sim_second)
    return rate, sim, ceiling, cpu


def _messages(run_dir: Path, nodes: list[str], group: tuple[str, ...]) -> dict[str, int]:
    """Messages each process handled: published and taken, from the bag's counts and the run's graph.yaml;
    ``group``: the nodes of the node group, whose messages are its process's.
    """
    counts = {name: topic.count for name, topic in read_bag(run_dir / 'bag').topics.items()}
    graph = yaml.safe_load((run_dir / 'graph.yaml').read_text())
    clocks = counts['/clock']
    handled = {}
    for node in nodes:
        published = sum(n for topic, n in counts.items() if node in graph.get(topic, {}).get('publishers', ()))
        taken = sum(n for topic, n in counts.items()
                    if topic != '/clock' and node in graph.get(topic, {}).get('subscribers', ()))
        handled[node] = published + taken + 3 * clocks
    handled['recorder'] = sum(counts.values()) + clocks
    handled['tethersim'] = clocks * (len(nodes) + 2)
    if group:
        handled[GROUP_NAME] = sum(handled.pop(node) for node in group)
    return handled


def _slug(label: str, config: str) -> str:
    """The name of a stage's run directory (and scene file) under --out."""
    return f'{label.strip("+ ").replace(" ", "-")}-{config}'


def run_stage(out: Path, label: str, nodes: dict, config: str,
              duration: float) -> tuple[float, float, list[NodeRow]]:
    """Run one stage with one configuration; return the real-time factor, the ceiling and the per-process rows."""
    slug = _slug(label, config)
    run_dir = out / slug
    scene = out / f'{slug}.yaml'
    _scene(scene, nodes, duration, CONFIGS[config])
    env = dict(os.environ, TETHERSIM_EXECUTOR=CONFIGS[config]['executor'])
    result = subprocess.run([sys.executable, '-m', 'tether_bringup.cli', 'run', str(scene), '--out', str(run_dir)],
                            env=env, capture_output=True, text=True, timeout=3600)
    if result.returncode != 0:
        raise SystemExit(f'graph_throughput: stage {label} ({config}) failed:\n{result.stderr[-2000:]}')
    rate, sim, ceiling, cpu = _summary(run_dir)
    group = tuple(node for node in nodes if node not in cpu)
    handled = _messages(run_dir, list(nodes), group)
    rows = [NodeRow(label, config, name, cpu[name], handled[name], sim) for name in cpu]
    return rate, ceiling, rows


def live_stage(out: Path, label: str, nodes: dict, duration: float) -> list[str] | None:
    """Run one stage in the ``group`` configuration with ``--live`` and a client subscribed to every topic;
    the report's lines (None without the client installed).
    """
    if shutil.which('node') is None or not (LIVE_CLIENT / 'node_modules').is_dir():
        return None
    slug = _slug(label, 'group') + '-live'
    run_dir = out / slug
    scene = out / f'{slug}.yaml'
    _scene(scene, nodes, duration, CONFIGS['group'])
    run = subprocess.Popen([sys.executable, '-m', 'tether_bringup.cli', 'run', str(scene), '--out', str(run_dir),
                            '--live', '0', '--live-wait'], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           text=True)
    stats = run_dir / 'live.yaml'
    while run.poll() is None and not stats.exists():
        time.sleep(0.05)
    url = yaml.safe_load(stats.read_text())['url'] if stats.exists() else None
    client = subprocess.Popen(['node', str(LIVE_CLIENT / 'client.mjs'), url, '--count', '*'],
                              stdout=subprocess.PIPE, text=True) if url else None
    _, errors = run.communicate(timeout=3600)
    if run.returncode != 0 or client is None:
        if client is not None:
            client.kill()
        raise SystemExit(f'graph_throughput: stage {label} (group, --live) failed:\n{errors[-2000:]}')
    received = sum(json.loads(client.communicate(timeout=60)[0].splitlines()[-1])['counts'].values())
    _, _, _, cpu = _summary(run_dir)
    served = yaml.safe_load(stats.read_text())
    live = cpu_per_sim_second(served)
    if live is None:
        raise SystemExit(f'graph_throughput: stage {label} (group, --live): the server sampled its CPU at fewer '
                         f'than two /clock values ({run_dir / "live.yaml"})')
    share = live / cpu[GROUP_NAME]
    _, _, _, plain = _summary(out / _slug(label, 'group'))
    return [f'live view ({label}, group, --live with a client subscribed to every topic): the server used '
            f'{live:.4f} CPU s per sim s, {share:.1%} of the node group\'s {cpu[GROUP_NAME]:.3f} (goal <= '
            f'{LIVE_GOAL:.0%}: {"met" if share <= LIVE_GOAL else "not met"}); it handed {served["served"]} of '
            f'{served["offered"]} messages to the Foxglove server, the client decoded {received}; the recorder '
            f'used {cpu["recorder"]:.3f} CPU s per sim s with it, {plain["recorder"]:.3f} in the run without']


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--duration', type=float, default=10.0, help='simulated seconds per stage (default 10)')
    parser.add_argument('--scene', help=f'scene of the last stage (default: the first installed of '
                                        f'{", ".join(FULLEST_SCENES)})')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-graph_throughput'))
    parser.add_argument('--live-only', action='store_true',
                        help='only the scene stage in the group configuration, without and with --live')
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    scene = args.scene or next(name for name in FULLEST_SCENES if _installed(name))
    if args.live_only:
        label = f'scene {scene}'
        run_stage(args.out, label, scene_nodes(scene), 'group', args.duration)
        text = '\n'.join(live_stage(args.out, label, scene_nodes(scene), args.duration) or [LIVE_MISSING]) + '\n'
        (args.out / 'live.txt').write_text(text)
        print(text, end='')
        return 0
    stages = dict(STAGES, **{f'scene {scene}': scene_nodes(scene)})
    quadratic = scene_nodes(scene)
    plants = [settings for settings in quadratic.values() if settings.get('executable') == 'plant']
    if plants:
        plants[0].setdefault('parameters', {}).update(QUADRATIC)
        stages[f'{scene} quadratic'] = quadratic
    rates: dict[tuple[str, str], float] = {}
    ceilings: dict[tuple[str, str], float] = {}
    rows: list[NodeRow] = []
    for label, nodes in stages.items():
        for config in CONFIGS:
            print(f'stage {label:<22} {config:<7} ...', file=sys.stderr, flush=True)
            rate, ceiling, stage_rows = run_stage(args.out, label, nodes, config, args.duration)
            rates[label, config], ceilings[label, config] = rate, ceiling
            rows += stage_rows

    print(f'stage {"scene " + scene:<22} group --live ...', file=sys.stderr, flush=True)
    live = live_stage(args.out, f'scene {scene}', stages[f'scene {scene}'], args.duration)

    cores = os.cpu_count() or 1
    names = list(CONFIGS)
    lines = [f'graph throughput, rate max, {args.duration:g} s simulated per stage, {cores} cores; '
             + '; '.join(f'{name}: {c["executor"]} executor, /clock every {c["clock_step"] * 1e3:g} ms, '
                         f'window {c["lockstep_window"] * 1e3:g} ms, '
                         + ('node group' if c['compose'] else 'a process per node') for name, c in CONFIGS.items()),
             '',
             'achieved real-time factor (RTF) and its CPU-bound ceiling (min of cores / total CPU per simulated '
             'second and 1 / the busiest main thread\'s, as the run summary prints it)',
             f'{"stage":<24} {"topics":>6} ' + ' '.join(f'{"RTF " + n:>11} {"ceil " + n:>11}' for n in names)]
    for label in stages:
        topics = len(read_bag(args.out / _slug(label, 'after') / 'bag').topics)
        cells = [f'{rates[label, name]:11.2f} {ceilings[label, name]:11.2f}' for name in names]
        lines.append(f'{label:<24} {topics:>6} ' + ' '.join(cells))
    if plants:
        rate, ceiling = rates[f'{scene} quadratic', 'group'], ceilings[f'{scene} quadratic', 'group']
        lines.append(f'goal: {scene} with quadratic elements at N = 20 at >= {GOAL:g}x real time in the node group: '
                     f'achieved {rate:.2f}x (ceiling {ceiling:.2f}x), {"met" if rate >= GOAL else "not met"}')
        summary = (args.out / _slug(f'{scene} quadratic', 'group') / 'summary.txt').read_text().splitlines()
        lines += [f'  in that run, {line}' for line in summary if line.startswith("the machine's")]
    lines += live or [LIVE_MISSING]
    lines += ['', 'CPU per message (us) and CPU per simulated second (s/s) per process',
              f'{"stage":<24} {"config":<7} {"process":<10} {"msgs":>8} {"us/msg":>8} {"s/s":>7}']
    for r in rows:
        lines.append(f'{r.stage:<24} {r.config:<7} {r.node:<10} {r.messages:8d} {r.us_per_message:8.1f} '
                     f'{r.cpu_per_sim_second:7.3f}')
    text = '\n'.join(lines) + '\n'
    (args.out / 'summary.txt').write_text(text)
    with open(args.out / 'table.csv', 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['stage', 'config', 'process', 'cpu_s', 'messages', 'us_per_message', 'cpu_per_sim_s',
                         'real_time_factor'])
        for r in rows:
            writer.writerow([r.stage, r.config, r.node, f'{r.cpu:.3f}', r.messages, f'{r.us_per_message:.1f}',
                             f'{r.cpu_per_sim_second:.4f}', f'{rates[r.stage, r.config]:.3f}'])
    print(text, end='')
    return 0


def _installed(name: str) -> bool:
    try:
        find_scene(name)
    except SceneError:
        return False
    return True


if __name__ == '__main__':
    sys.exit(main())
