"""Helpers of the cross-package tests: run the tethersim command line in a subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / 'test' / 'scenes'


def tethersim(*args: str, timeout: float = 180.0, **kwargs) -> subprocess.CompletedProcess:
    """Run ``tethersim ARGS`` in the current environment and capture its output."""
    return subprocess.run([sys.executable, '-m', 'tether_bringup', *args], capture_output=True,
                          text=True, timeout=timeout, cwd=kwargs.pop('cwd', ROOT), **kwargs)


def start_tethersim(*args: str, **kwargs) -> subprocess.Popen:
    """Start ``tethersim ARGS`` without waiting for it (output piped unless given)."""
    kwargs.setdefault('stdout', subprocess.PIPE)
    kwargs.setdefault('stderr', subprocess.PIPE)
    return subprocess.Popen([sys.executable, '-m', 'tether_bringup', *args], text=True, cwd=ROOT, **kwargs)


def processes_of(run_dir: Path) -> list[psutil.Process]:
    """Processes still running whose command line names ``run_dir`` (the run's nodes)."""
    found = []
    for process in psutil.process_iter(['cmdline', 'pid']):
        cmdline = ' '.join(process.info['cmdline'] or [])
        if str(run_dir) in cmdline and process.info['pid'] != os.getpid():
            found.append(process)
    return found
