"""Helpers of the campaign tests: short specs, and a watch on every process a command starts."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import psutil
import yaml

TIMING = ('wall_time', 'realtime_factor', 'cpu_per_sim_s', 'cpu_time')
"""Figures of a run that depend on the machine's load, not on what was simulated."""


def write_spec(path: Path, **spec) -> Path:
    """Write a campaign spec; return its path."""
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def simulated(figures: dict) -> dict:
    """A run's figures without those that depend on the machine's load."""
    return {key: value for key, value in figures.items() if key not in TIMING}


def run_figures(run_dir: Path) -> dict:
    """A run directory's ``figures.json``."""
    return json.loads((run_dir / 'figures.json').read_text())


class ProcessWatch:
    """Every process descended from ``root`` while the watch runs (sampled every 0.1 s), to check none is left."""

    def __init__(self, root: int) -> None:
        self.seen: dict[tuple[int, float], psutil.Process] = {}
        self._root = psutil.Process(root)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()

    def _sample(self) -> None:
        while not self._stop.is_set():
            try:
                for process in self._root.children(recursive=True):
                    try:
                        self.seen.setdefault((process.pid, process.create_time()), process)
                    except psutil.Error:
                        pass
            except psutil.Error:
                return
            time.sleep(0.1)

    def left_behind(self, grace: float = 30.0) -> list[str]:
        """Stop watching; the processes seen that are still running after up to ``grace`` s, as name and command line."""
        self._stop.set()
        self._thread.join()
        deadline = time.monotonic() + grace
        while True:
            alive = [p for p in self.seen.values() if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
            if not alive or time.monotonic() > deadline:
                break
            time.sleep(0.5)
        described = []
        for process in alive:
            try:
                described.append(f'{process.pid} {process.name()}: {" ".join(process.cmdline())[:200]}')
            except psutil.Error:
                pass
        return described
