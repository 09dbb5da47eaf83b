"""One run of a campaign, as a Ray task: ``tethersim run`` of the run's scene file, in a process tree of its own.

The task writes the run's scene into its directory and runs ``python -m tether_bringup run
SCENE --out DIR`` there, exactly the command that reruns it alone. The bringup reserves the
run's private ``ROS_DOMAIN_ID`` (``domain_coordinator``) and records the bag, summary, plots
and ``figures.json``. The run's process group is its own; it gets SIGTERM when the task's
worker dies (``PR_SET_PDEATHSIG``), and a cancelled task (Ctrl-C of the campaign,
``ray.cancel``) interrupts it as Ctrl-C would and waits for it to finalize its bag.

On a node that does not see the campaign directory (a cluster without a shared file system:
the campaign's token file is not there), the run happens in a temporary directory whose
files travel back with the result as a tar archive, and the directory is removed.
"""

from __future__ import annotations

import contextlib
import ctypes
import io
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tarfile
import tempfile
import time
from collections import deque
from pathlib import Path

TOKEN_FILE = '.campaign-token'
FIGURES_FILE = 'figures.json'
LOG_FILE = 'tethersim.log'
STOP_TIMEOUT = 120.0
"""s a run may take to stop and finalize its bag after Ctrl-C before its processes are killed."""
KEPT_WHEN_PRUNED = (FIGURES_FILE, 'summary.txt', LOG_FILE)
"""What is kept of a run's directory that ``--keep failed`` prunes: its scene, figures, summary and log."""
_PR_SET_PDEATHSIG = 1


def _die_with_parent() -> None:
    """In the run's process before it starts: SIGTERM when the task's worker dies, and SIGINT and SIGTERM acted on
    (a Ray worker ignores SIGINT, which the run would inherit and so not stop on Ctrl-C).
    """
    ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, (signal.SIGINT, signal.SIGTERM))


def run_command(scene_file: Path, run_dir: Path) -> list[str]:
    """The command that runs a campaign's run (and reruns it alone)."""
    return [sys.executable, '-m', 'tether_bringup', 'run', str(scene_file), '--out', str(run_dir)]


def _reason(log: Path, status: int) -> str:
    """Why a run failed: the bringup's error line (or its log's last line) and its exit status."""
    try:
        with open(log, errors='replace') as file:
            lines = [line.rstrip() for line in deque(file, maxlen=200)]
    except OSError:
        lines = []
    errors = [line.removeprefix('tethersim: error: ') for line in lines if line.startswith('tethersim: error: ')]
    last = errors[-1] if errors else next((line for line in reversed(lines) if line.strip()), 'no output')
    return f'exit status {status}: {last}'


def _stop(process: subprocess.Popen) -> None:
    """Interrupt the run like Ctrl-C; kill its process group if it has not ended within STOP_TIMEOUT."""
    try:
        os.killpg(process.pid, signal.SIGINT)
        process.wait(STOP_TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    except ProcessLookupError:
        process.wait()


def _run(scene_file: Path, run_dir: Path) -> int:
    """Run the scene into ``run_dir``; return the exit status. A KeyboardInterrupt stops the run first."""
    with open(run_dir / LOG_FILE, 'wb') as log:
        process = subprocess.Popen(run_command(scene_file, run_dir), stdin=subprocess.DEVNULL, stdout=log,
                                   stderr=subprocess.STDOUT, process_group=0, preexec_fn=_die_with_parent)
        try:
            while process.poll() is None:  # polled, so that a cancel's KeyboardInterrupt arrives at once
                time.sleep(0.1)
        except BaseException:
            _stop(process)
            raise
    return process.returncode


def _archive(directory: Path) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode='w') as tar:
        for path in sorted(directory.iterdir()):
            tar.add(path, arcname=path.name)
    return buffer.getvalue()


def prune(run_dir: Path, scene_name: str) -> None:
    """Remove a run directory's bag, plots and logs, keeping its scene, figures, summary and log."""
    for path in run_dir.iterdir():
        if path.name in (*KEPT_WHEN_PRUNED, scene_name):
            continue
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink()


def _processes_of(run_dir: Path) -> list[int]:
    """The processes on this node whose command line names ``run_dir`` (a run's bringup and nodes)."""
    marker = str(run_dir).encode()
    found = []
    for entry in Path('/proc').iterdir():
        if entry.name.isdigit() and int(entry.name) != os.getpid():
            try:
                if marker in (entry / 'cmdline').read_bytes():
                    found.append(int(entry.name))
            except OSError:
                pass
    return found


def _wait_for_earlier_attempt(run_dir: Path) -> None:
    """Wait until an earlier attempt's processes here have ended (a worker killed under a run: its bringup,
    sent SIGTERM, is still finalizing the bag into ``run_dir``); kill them after STOP_TIMEOUT.
    """
    deadline = time.monotonic() + STOP_TIMEOUT
    while (left := _processes_of(run_dir)) and time.monotonic() < deadline:
        time.sleep(0.2)
    for pid in left:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)


def run_scene(request: dict) -> dict:
    """Run one campaign run; return its result.

    ``request``: ``campaign_dir``, ``token``, ``run_name``, ``scene_name`` (file name), ``scene_text``
    (the run's scene YAML), ``prune_ok`` (prune the directory of a run that succeeded).

    Returns: ``exit_status``, ``reason`` (None when it succeeded), ``figures`` (``figures.json``,
    {} without one), ``node_id``, ``hostname``, ``wall_time`` (s), and ``archive`` (the
    directory as a tar, when the node does not see the campaign directory; else None).
    """
    import ray

    campaign_dir = Path(request['campaign_dir'])
    token_file = campaign_dir / TOKEN_FILE
    shared = token_file.is_file() and token_file.read_text().strip() == request['token']
    temporary = None if shared else Path(tempfile.mkdtemp(prefix=f'tethersim-{request["run_name"]}-'))
    run_dir = campaign_dir / 'runs' / request['run_name'] if shared else temporary / request['run_name']
    if run_dir.exists():  # an earlier attempt's (a retry, or a run interrupted before --resume)
        _wait_for_earlier_attempt(run_dir)
        shutil.rmtree(run_dir)
    run_dir.mkdir(parents=True)
    scene_file = run_dir / request['scene_name']
    scene_file.write_text(request['scene_text'])
    start = time.monotonic()
    try:
        status = _run(scene_file, run_dir)
        figures_file = run_dir / FIGURES_FILE
        figures = json.loads(figures_file.read_text()) if figures_file.is_file() else {}
        ok = status == 0 and bool(figures)
        reason = None if ok else _reason(run_dir / LOG_FILE, status) if status else 'no figures.json written'
        if ok and request['prune_ok']:
            prune(run_dir, request['scene_name'])
        return {'exit_status': status, 'reason': reason, 'figures': figures,
                'node_id': ray.get_runtime_context().get_node_id(), 'hostname': socket.gethostname(),
                'wall_time': time.monotonic() - start, 'archive': None if shared else _archive(run_dir)}
    finally:
        if temporary is not None:
            shutil.rmtree(temporary, ignore_errors=True)
