"""Campaign throughput: ``tethersim sweep`` on the local Ray instance against a sequential loop of ``tethersim run``.

Both run the same scenes, in the same benchmark run: the runs of a campaign of the default
mission (``outdoor_flight``, its platform and sensor seeds drawn per run, one CPU per run) —
first as a campaign (``tethersim sweep``, a local Ray instance with the machine's cores),
then each run's scene file one after another (``tethersim run``). Per side:

* runs per hour: runs / wall time, the campaign's including Ray's start and stop;
* CPU utilisation: the CPU seconds of the side's whole process tree (every process descended
  from the side's command, sampled from ``/proc``: the sweep, Ray's processes and workers, every
  run's bringup, recorder and node group) over wall time x cores; and the machine's busy share over
  the same time (``/proc/stat``: every process on the machine, other people's too);
* the runs' CPU utilisation: their ``figures.json`` ``cpu_time`` (bringup and nodes, start-up
  included) over wall time x cores, which Ray's own processes are not in;
* per-run start-up overhead: each run's wall time outside its simulation, ``tethersim run``'s
  start (Python imports, nodes started, the recorder subscribed, every node joined) and
  shutdown (bag finalized, reports): the task's or the loop's wall time for the run minus the
  sim time over the achieved real-time factor of ``figures.json``; the mean over the runs.

The goal of issue 34: the campaign at >= 1.7x the loop's runs per hour on 2 cores, >= 90 % of
the cores busy. The last line checks that each campaign run's figures (load-dependent ones
aside) equal its loop run's. Writes ``summary.txt`` to --out.

Run:  ./tethersim-env python bench/campaign/run.py [--runs 20] [--duration S] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import psutil
import pyarrow.parquet as pq
import yaml

from tether_bringup.machine_load import core_times

TIMING = ('wall_time', 'realtime_factor', 'cpu_per_sim_s', 'cpu_time')


class TreeCpu:
    """CPU seconds of every process descended from ``root``, each read from ``/proc`` every 0.1 s until it ends.

    Each process's own user + system time at its last sample (not its children's, which are
    processes of the tree too); a process's last 0.1 s before it ends may be missed.
    """

    def __init__(self, root: int) -> None:
        self._root = psutil.Process(root)
        self._seen: dict[tuple[int, float], float] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()

    def _sample(self) -> None:
        while not self._stop.is_set():
            try:
                processes = [self._root, *self._root.children(recursive=True)]
            except psutil.Error:
                return
            for process in processes:
                try:
                    times = process.cpu_times()
                    self._seen[(process.pid, process.create_time())] = times.user + times.system
                except psutil.Error:
                    pass
            time.sleep(0.1)

    def total(self) -> float:
        """Stop sampling; the tree's CPU seconds."""
        self._stop.set()
        self._thread.join()
        return sum(self._seen.values())


def _measure(command: list[str]) -> tuple[float, float, float, subprocess.CompletedProcess]:
    """Run ``command``; return its wall time, its process tree's CPU s, the machine's busy core-s, the result."""
    machine, start = core_times(), time.monotonic()
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    tree = TreeCpu(process.pid)
    stdout, stderr = process.communicate()
    wall = time.monotonic() - start
    cpu = tree.total()
    end = core_times()
    busy = end.busy - machine.busy if end is not None and machine is not None else float('nan')
    return wall, cpu, busy, subprocess.CompletedProcess(command, process.returncode, stdout, stderr)


def _overhead(wall: float, figures: dict) -> float:
    return wall - figures['sim_time'] / figures['realtime_factor']


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n', 1)[0])
    parser.add_argument('--runs', type=int, default=20, help='runs on each side (default 20)')
    parser.add_argument('--duration', type=float, help='sim time of each run, s (default: the scene\'s, 255 s)')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-campaign'), help='output directory')
    args = parser.parse_args()
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    cores = os.cpu_count() or 1
    spec = {'description': 'bench: the default mission', 'scene': 'outdoor_flight', 'count': args.runs,
            'random': {'platform.seed': {'range': [1, 1000000]}, 'sensors.seed': {'range': [1, 1000000]}}}
    if args.duration:
        spec['set'] = {'duration': args.duration}
    spec_file = out / 'bench.yaml'
    spec_file.write_text(yaml.safe_dump(spec, sort_keys=False))
    tethersim = [sys.executable, '-m', 'tether_bringup']

    campaign = out / 'campaign'
    wall_c, cpu_c, busy_c, result = _measure([*tethersim, 'sweep', str(spec_file), '--out', str(campaign)])
    if result.returncode != 0:
        print(result.stderr, file=sys.stderr)
        return 1
    rows = pq.read_table(campaign / 'results.parquet').to_pylist()

    loop_walls, loop_figures = [], []
    cpu_l = busy_l = 0.0
    wall_l = 0.0
    for row in rows:
        solo = out / 'loop' / row['run']
        scene = campaign / 'runs' / row['run'] / 'outdoor_flight.yaml'
        wall, cpu, busy, done = _measure([*tethersim, 'run', str(scene), '--out', str(solo)])
        if done.returncode != 0:
            print(done.stderr, file=sys.stderr)
            return 1
        loop_walls.append(wall)
        loop_figures.append(json.loads((solo / 'figures.json').read_text()))
        wall_l, cpu_l, busy_l = wall_l + wall, cpu_l + cpu, busy_l + busy

    n = len(rows)
    campaign_figures = [json.loads((campaign / 'runs' / row['run'] / 'figures.json').read_text()) for row in rows]
    over_c = sum(_overhead(row['task_time'], f) for row, f in zip(rows, campaign_figures)) / n
    over_l = sum(_overhead(w, f) for w, f in zip(loop_walls, loop_figures)) / n
    sim = campaign_figures[0]['sim_time']
    equal = all({k: v for k, v in a.items() if k not in TIMING} == {k: v for k, v in b.items() if k not in TIMING}
                for a, b in zip(campaign_figures, loop_figures))
    speedup = wall_l / wall_c
    runs_c = sum(f['cpu_time'] for f in campaign_figures) / (wall_c * cores)
    runs_l = sum(f['cpu_time'] for f in loop_figures) / (wall_l * cores)
    lines = [
        f'bench/campaign: {n} runs of outdoor_flight, {sim:g} s of sim time each, on {cores} cores',
        f'{"":<10} {"wall s":>8} {"runs/hour":>10} {"CPU util.":>10} {"runs CPU":>10} {"machine busy":>13} '
        f'{"start-up s/run":>15}',
        f'{"campaign":<10} {wall_c:8.1f} {3600 * n / wall_c:10.1f} {cpu_c / (wall_c * cores):10.1%} {runs_c:10.1%} '
        f'{busy_c / (wall_c * cores):13.1%} {over_c:15.1f}',
        f'{"loop":<10} {wall_l:8.1f} {3600 * n / wall_l:10.1f} {cpu_l / (wall_l * cores):10.1%} {runs_l:10.1%} '
        f'{busy_l / (wall_l * cores):13.1%} {over_l:15.1f}',
        f'campaign / loop: {speedup:.2f}x the runs per hour (goal >= 1.7x: {"met" if speedup >= 1.7 else "not met"}); '
        f'the campaign\'s process tree kept {cpu_c / (wall_c * cores):.0%} of the cores busy (goal >= 90 %: '
        f'{"met" if cpu_c / (wall_c * cores) >= 0.9 else "not met"})',
        'CPU util.: the side\'s own process tree (sampled); runs CPU: the runs\' figures.json cpu_time '
        '(each run\'s bringup and nodes, start-up included); machine busy: every process on the machine (other people\'s too); '
        'start-up s/run: a run\'s wall time outside its simulation (start, shutdown, reports), the campaign\'s '
        'measured in its Ray task',
        f'every campaign run\'s figures equal its loop run\'s (load-dependent ones aside): {"yes" if equal else "NO"}',
    ]
    text = '\n'.join(lines) + '\n'
    (out / 'summary.txt').write_text(text)
    print(text, end='')
    return 0


if __name__ == '__main__':
    sys.exit(main())
