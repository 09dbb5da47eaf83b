"""Graph throughput: real-time factor and CPU per message per node as nodes and topics are added.

Each stage is a scene run with ``tethersim run --rate max`` (lockstep: as fast as the
slowest process allows), twice in the same benchmark run: with rclpy's default
``SingleThreadedExecutor`` in every process (the baseline, ``TETHERSIM_EXECUTOR=single``)
and with the ``EventsExecutor`` the nodes use. Stages:

1. ``platform``: the platform node (4 topics at 100 Hz) and the recorder;
2. ``+ plant``: the tether plant of ``tether_demo`` (quasi-static, 3 topics at 100 Hz, 2 at 10 Hz);
3. ``+ reel``: the smart reel node on /tether/state and /truth/relative (1 topic at 100 Hz, 2 at 50 Hz);
4. ``+ load``: two load nodes (``load_node.py``, 3 Imu topics at 100 Hz each) standing in for
   the sensor, estimator and UAV nodes not in the graph yet.

Per node it reports CPU seconds (from the run summary), messages handled (published, acks
included, plus taken: inputs, both /clock subscriptions of a lockstep node, every topic for
the recorder, the acks for the time master ``tethersim``) counted from the bag, CPU per
message, and CPU per simulated second. Writes ``summary.txt`` and ``table.csv`` to --out.

Run:  ./tethersim-env python bench/graph_throughput/run.py [--duration 10] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import yaml

from tether_bringup.bag_reader import read_bag

HERE = Path(__file__).resolve().parent
EXECUTORS = ('single', 'events')
PLATFORM = {'package': 'psr_platform_sim', 'executable': 'platform',
            'parameters': {'profile': 'hpr1', 'seed': 1, 'profile_duration': 60.0}}
PLANT = {'package': 'tether_dynamics', 'executable': 'plant',
         'parameters': {'fidelity': 'quasi_static', 'integration_step': 0.01, 'state_rate': 100.0,
                        'nodes_rate': 10.0, 'markers_rate': 10.0, 'reel_input': 'reference',
                        'uav_source': 'fixed', 'uav_position': [3.22, 0.0, 5.9]}}
REEL = {'package': 'smart_reel', 'executable': 'reel', 'parameters': {'relative_source': 'truth'}}
STAGES = (
    ('platform', {'platform': PLATFORM}),
    ('+ plant', {'platform': PLATFORM, 'plant': PLANT}),
    ('+ reel', {'platform': PLATFORM, 'plant': PLANT, 'reel': REEL}),
    ('+ load', {'platform': PLATFORM, 'plant': PLANT, 'reel': REEL,
                'load_a': {'script': str(HERE / 'load_node.py'), 'parameters': {'topics': 3}},
                'load_b': {'script': str(HERE / 'load_node.py'), 'parameters': {'topics': 3}}}),
)
# What each node publishes (topic prefixes) and takes (topics), to count its messages from the bag.
PUBLISHES = {'platform': ('/platform/',), 'plant': ('/tether/', '/truth/'), 'reel': ('/reel/',),
             'load_a': ('/bench/load_a_',), 'load_b': ('/bench/load_b_',), 'tethersim': ('/clock',)}
TAKES = {'platform': (), 'plant': ('/platform/reel_pose', '/platform/reel_twist'),
         'reel': ('/tether/state', '/truth/relative'), 'load_a': ('/platform/imu',), 'load_b': ('/platform/imu',)}


@dataclass
class NodeRow:
    stage: str
    executor: str
    node: str
    cpu: float
    messages: int
    sim_time: float

    @property
    def us_per_message(self) -> float:
        return self.cpu / self.messages * 1e6 if self.messages else float('nan')

    @property
    def cpu_per_sim_second(self) -> float:
        return self.cpu / self.sim_time


def _scene(path: Path, nodes: dict, duration: float) -> None:
    path.write_text(yaml.safe_dump({'description': 'graph throughput stage', 'duration': duration,
                                    'rate': 'max', 'clock_step': 0.01, 'nodes': nodes}, sort_keys=False))


def _summary(run_dir: Path) -> tuple[float, float, dict[str, float]]:
    """Achieved real-time factor, simulated time and CPU seconds per process from summary.txt."""
    lines = (run_dir / 'summary.txt').read_text().splitlines()
    rate = sim = None
    cpu = {}
    in_table = False
    for line in lines:
        if 'achieved real-time factor' in line:
            sim = float(line.split('simulated ')[1].split(' s')[0])
            rate = float(line.split('achieved real-time factor ')[1].split()[0])
        elif line.startswith('node '):
            in_table = True
        elif in_table and len(line.split()) == 4:
            name, _, cpu_s, _ = line.split()
            cpu[name] = float(cpu_s)
        elif in_table:
            in_table = False
    return rate, sim, cpu


def _messages(run_dir: Path, nodes: list[str]) -> dict[str, int]:
    """Messages each process handled: published (and acks) plus taken."""
    counts = {name: topic.count for name, topic in read_bag(run_dir / 'bag').topics.items()}
    steps = counts['/clock']
    handled = {}
    for node in nodes:
        published = sum(n for topic, n in counts.items() if topic.startswith(PUBLISHES[node]))
        taken = sum(counts.get(topic, 0) for topic in TAKES[node])
        handled[node] = published + steps + taken + 2 * steps
    handled['recorder'] = sum(counts.values()) + steps
    handled['tethersim'] = steps + steps * (len(nodes) + 1)
    return handled


def run_stage(out: Path, label: str, nodes: dict, executor: str, duration: float) -> tuple[float, list[NodeRow]]:
    """Run one stage with one executor; return the real-time factor and the per-node rows."""
    slug = f'{label.strip("+ ")}-{executor}'
    run_dir = out / slug
    scene = out / f'{slug}.yaml'
    _scene(scene, nodes, duration)
    env = dict(os.environ, TETHERSIM_EXECUTOR=executor)
    result = subprocess.run([sys.executable, '-m', 'tether_bringup.cli', 'run', str(scene), '--out', str(run_dir)],
                            env=env, capture_output=True, text=True, timeout=1800)
    if result.returncode != 0:
        raise SystemExit(f'graph_throughput: stage {label} ({executor}) failed:\n{result.stderr[-2000:]}')
    rate, sim, cpu = _summary(run_dir)
    handled = _messages(run_dir, list(nodes))
    rows = [NodeRow(label, executor, name, cpu[name], handled[name], sim) for name in ['tethersim', 'recorder', *nodes]]
    return rate, rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--duration', type=float, default=10.0, help='simulated seconds per stage (default 10)')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-graph_throughput'))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    rates: dict[tuple[str, str], float] = {}
    rows: list[NodeRow] = []
    for label, nodes in STAGES:
        for executor in EXECUTORS:
            print(f'stage {label:<9} executor {executor:<6} ...', file=sys.stderr, flush=True)
            rate, stage_rows = run_stage(args.out, label, nodes, executor, args.duration)
            rates[label, executor] = rate
            rows += stage_rows

    lines = [f'graph throughput, rate max, {args.duration:g} s simulated per stage, clock step 10 ms, '
             f'{os.cpu_count()} cores',
             '',
             f'{"stage":<10} {"topics":>6} {"RTF single":>11} {"RTF events":>11} {"ratio":>6}']
    for label, _nodes in STAGES:
        topics = len(read_bag(args.out / f'{label.strip("+ ")}-events' / 'bag').topics)
        single, events = rates[label, 'single'], rates[label, 'events']
        lines.append(f'{label:<10} {topics:>6} {single:11.2f} {events:11.2f} {events / single:6.2f}')
    lines += ['', 'CPU per message (us) and CPU per simulated second (s/s) per process',
              f'{"stage":<10} {"process":<10} {"msgs":>7} {"us/msg single":>14} {"us/msg events":>14} '
              f'{"s/s single":>11} {"s/s events":>11}']
    by_key = {(r.stage, r.executor, r.node): r for r in rows}
    for label, nodes in STAGES:
        for node in ['tethersim', 'recorder', *nodes]:
            single, events = by_key[label, 'single', node], by_key[label, 'events', node]
            lines.append(f'{label:<10} {node:<10} {events.messages:7d} {single.us_per_message:14.1f} '
                         f'{events.us_per_message:14.1f} {single.cpu_per_sim_second:11.3f} '
                         f'{events.cpu_per_sim_second:11.3f}')
    text = '\n'.join(lines) + '\n'
    (args.out / 'summary.txt').write_text(text)
    with open(args.out / 'table.csv', 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(['stage', 'executor', 'process', 'cpu_s', 'messages', 'us_per_message', 'cpu_per_sim_s',
                         'real_time_factor'])
        for r in rows:
            writer.writerow([r.stage, r.executor, r.node, f'{r.cpu:.3f}', r.messages, f'{r.us_per_message:.1f}',
                             f'{r.cpu_per_sim_second:.4f}', f'{rates[r.stage, r.executor]:.3f}'])
    print(text, end='')
    return 0


if __name__ == '__main__':
    sys.exit(main())
