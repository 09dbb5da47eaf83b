"""``tethersim sweep SPEC``: a campaign's runs as Ray tasks, each one ``tethersim run`` of its scene file.

Without ``--address`` the command starts a private local Ray instance with the machine's cores
(no dashboard, a small object store, a temporary directory and an authentication token of its
own) and shuts it down at the end; with ``--address`` it connects to an existing cluster and
the same tasks run on its nodes. Each run reserves the spec's ``cpus`` on the node it runs
on (:func:`tether_campaign.task.run_scene`). At most ``--workers`` runs are under way at once
(default: as many as the cluster's CPUs hold).

A run that fails (a non-zero exit, a worker killed, a node lost) is tried again up to the
spec's ``retries`` times and then recorded as failed with its reason; the campaign goes on.
Each finished run is recorded at once (:mod:`tether_campaign.results`), so ``--resume``
runs only the runs without a record. Ctrl-C cancels the runs under way (each stops like a
``tethersim run`` on Ctrl-C, finalizing its bag), keeps what finished, and shuts the local
Ray instance down: no process is left behind; a second Ctrl-C kills the runs' workers.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import secrets
import shutil
import socket
import sys
import tarfile
import tempfile
import time
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import yaml

from tether_bringup.errors import TethersimError
from tether_campaign.results import CSV
from tether_campaign.results import PARQUET
from tether_campaign.results import read_rows
from tether_campaign.results import write_row
from tether_campaign.results import write_tables
from tether_campaign.spec import Campaign
from tether_campaign.task import STOP_TIMEOUT
from tether_campaign.task import TOKEN_FILE
from tether_campaign.task import run_scene

STATE_FILE = 'campaign.yaml'
"""The campaign directory's record of its spec: the spec's text and a fingerprint of its runs' scenes."""
OBJECT_STORE_BYTES = 128 * 2**20
"""The local Ray instance's object store: results are small (figures), archives only from nodes without the directory."""
PROGRESS_PERIOD = 10.0
"""s between progress lines when stderr is not a terminal."""


class SweepError(TethersimError):
    """The campaign cannot start: its directory holds another campaign, or the Ray cluster cannot be reached."""


@dataclass
class SweepOptions:
    """How a campaign runs."""

    out: Path
    address: str | None = None
    workers: int | None = None
    resume: bool = False
    keep: str = 'all'
    retries: int | None = None


def fingerprint(campaign: Campaign) -> str:
    """SHA-256 of every run's scene: a resumed campaign must run the scenes its first part ran."""
    digest = hashlib.sha256()
    for index in range(campaign.size):
        digest.update(yaml.safe_dump(campaign.scene_data(index), sort_keys=True).encode())
    return digest.hexdigest()


def _prepare(campaign: Campaign, options: SweepOptions) -> str:
    """Make or check the campaign directory; write a fresh token; return it."""
    out = options.out
    state = out / STATE_FILE
    marks = fingerprint(campaign)
    if state.is_file():
        if not options.resume:
            raise SweepError(f'{out}: already holds a campaign; give --resume to finish it, or another --out')
        recorded = yaml.safe_load(state.read_text()) or {}
        if recorded.get('fingerprint') != marks:
            raise SweepError(f'{out}: holds a campaign of other scenes than {campaign.path} gives now (the spec or '
                             'its base scene changed); give another --out')
    elif out.exists() and any(out.iterdir()):
        raise SweepError(f'{out}: not empty and not a campaign directory; give another --out')
    else:
        out.mkdir(parents=True, exist_ok=True)
        state.write_text(yaml.safe_dump({'spec': str(campaign.path.resolve()), 'scene': str(campaign.scene_path),
                                         'runs': campaign.size, 'factors': campaign.factors,
                                         'grid': list(campaign.grid), 'fingerprint': marks,
                                         'spec_text': campaign.path.read_text()}, sort_keys=False))
    token = secrets.token_hex(16)
    (out / TOKEN_FILE).write_text(token + '\n')
    return token


@contextlib.contextmanager
def ray_cluster(address: str | None) -> Iterator[None]:
    """Connected to Ray: the cluster at ``address``, or a private local instance started here and shut down after.

    The local instance's token is made here and given to its processes in the environment
    (``RAY_AUTH_TOKEN``), which Ray reads when it is first imported: nothing is written to
    ``~/.ray``. A cluster's own authentication is left as its administrator set it.
    """
    saved = {name: os.environ.get(name) for name in ('RAY_AUTH_MODE', 'RAY_AUTH_TOKEN', 'RAY_USAGE_STATS_ENABLED')}
    os.environ.setdefault('RAY_USAGE_STATS_ENABLED', '0')
    if address is None:
        os.environ.update(RAY_AUTH_MODE='token', RAY_AUTH_TOKEN=secrets.token_hex(32))
    import ray

    temp_dir = None
    try:
        if address is None:
            temp_dir = tempfile.mkdtemp(prefix='tethersim-ray-')
            try:
                ray.init(address='local', num_cpus=os.cpu_count(), include_dashboard=False, log_to_driver=False,
                         object_store_memory=OBJECT_STORE_BYTES, _temp_dir=temp_dir, logging_level=logging.WARNING)
            except Exception as error:  # Ray raises a bare Exception when its raylet does not register in 30 s
                raise SweepError(f'cannot start a local Ray instance: {_first_line(error)}') from None
        else:
            try:
                ray.init(address=address, log_to_driver=False, logging_level=logging.WARNING)
            except (ConnectionError, ValueError, RuntimeError) as error:
                raise SweepError(f'cannot connect to the Ray cluster at {address}: {_first_line(error)}') from None
        yield
    finally:
        if ray.is_initialized():
            ray.shutdown()
        if temp_dir is not None:
            shutil.rmtree(temp_dir, ignore_errors=True)
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _first_line(error: Exception) -> str:
    text = str(error).strip()
    return text.splitlines()[0] if text else type(error).__name__


class Progress:
    """The campaign's progress line on stderr: runs done, failed, under way, and the time left at the rate so far."""

    def __init__(self, name: str, total: int, done: int) -> None:
        self.name, self.total, self.done, self.failed = name, total, done, 0
        self.start_done = done
        self.start = time.monotonic()
        self.interactive = sys.stderr.isatty()
        self._last = 0.0

    def line(self, running: int) -> str:
        """The progress line now."""
        finished = self.done - self.start_done
        elapsed = time.monotonic() - self.start
        left = self.total - self.done
        eta = f'{_duration(elapsed / finished * left)}' if finished else '-'
        return (f'sweep {self.name}: {self.done}/{self.total} done, {self.failed} failed, {running} running, '
                f'{_duration(elapsed)} elapsed, ETA {eta}')

    def show(self, running: int, force: bool = False) -> None:
        """Print the line: at once on a terminal, else every PROGRESS_PERIOD or when ``force``d."""
        now = time.monotonic()
        if self.interactive:
            print('\r' + self.line(running) + '\033[K', end='', file=sys.stderr, flush=True)
        elif force or now - self._last >= PROGRESS_PERIOD:
            print(self.line(running), file=sys.stderr, flush=True)
        self._last = now

    def note(self, text: str) -> None:
        """A line of its own (a failed attempt), above the progress line."""
        print(('\r\033[K' if self.interactive else '') + text, file=sys.stderr, flush=True)


def _duration(seconds: float) -> str:
    minutes, secs = divmod(int(round(seconds)), 60)
    hours, minutes = divmod(minutes, 60)
    return f'{hours}h{minutes:02d}m' if hours else f'{minutes}m{secs:02d}s'


def _request(campaign: Campaign, index: int, out: Path, token: str, keep: str) -> dict:
    return {'campaign_dir': str(out.resolve()), 'token': token, 'run_name': campaign.run_name(index),
            'scene_name': campaign.scene_path.name,
            'scene_text': yaml.safe_dump(campaign.scene_data(index), sort_keys=False),
            'prune_ok': keep == 'failed'}


def _node_names() -> dict[str, str]:
    import ray
    return {node['NodeID']: node.get('NodeName') or node.get('NodeManagerAddress', '') for node in ray.nodes()}


def _row(campaign: Campaign, index: int, out: Path, attempts: int, result: dict | None, reason: str | None,
         nodes: dict[str, str]) -> dict:
    """The results row of a finished run."""
    name = campaign.run_name(index)
    values = campaign.values(index)
    row = {'index': index, 'run': name, 'status': 'ok' if reason is None else 'failed', 'attempts': attempts,
           'reason': reason, 'node': None, 'node_id': None, 'hostname': None, 'task_time': None,
           'command': f'tethersim run {out.resolve() / "runs" / name / campaign.scene_path.name} --out runs/rerun-{name}'}
    if result is not None:
        row.update(node=nodes.get(result['node_id'], result['node_id']), node_id=result['node_id'],
                   hostname=result['hostname'], task_time=result['wall_time'])
    row.update({key: values[key] for key in campaign.factors})
    for key, value in (result or {}).get('figures', {}).items():
        row[f'figure.{key}' if key in row else key] = value
    return row


def _unpack(archive: bytes, run_dir: Path) -> None:
    """Put a run's directory that came back from a node without the campaign directory in its place."""
    import io
    if run_dir.exists():
        shutil.rmtree(run_dir)
    run_dir.mkdir(parents=True)
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(run_dir, filter='data')


def _run_missing(campaign: Campaign, options: SweepOptions, out: Path, token: str, retries: int, todo: deque,
                 progress: Progress) -> bool:
    """Run the runs in ``todo`` on Ray, recording each as it finishes; return whether Ctrl-C stopped them."""
    interrupted = False
    with ray_cluster(options.address):
        import ray  # after ray_cluster set the environment it reads on import
        from ray.exceptions import RayError
        from ray.exceptions import TaskCancelledError

        cpus = ray.cluster_resources().get('CPU', 0.0)
        workers = options.workers or max(1, int(cpus // campaign.cpus))
        if cpus < campaign.cpus:
            raise SweepError(f'the Ray cluster has {cpus:g} CPUs; a run of {campaign.path} reserves '
                             f'{campaign.cpus:g} (cpus)')
        progress.note(f'sweep {campaign.name}: {len(todo)} runs of {campaign.scene_path.stem}, up to {min(workers, len(todo))} at a '
                      f'time on {len(ray.nodes())} Ray node(s) with {cpus:g} CPUs, {campaign.cpus:g} CPU(s) '
                      f'each, {retries} retries')
        remote = ray.remote(run_scene).options(num_cpus=campaign.cpus, max_retries=0)
        attempts = dict.fromkeys(todo, 0)
        pending: dict = {}
        nodes = _node_names()

        def finish(index: int, result: dict | None, reason: str | None) -> None:
            if result is not None and result.get('archive'):
                _unpack(result['archive'], out / 'runs' / campaign.run_name(index))
            if result is not None and result['node_id'] not in nodes:
                nodes.update(_node_names())
            write_row(out, _row(campaign, index, out, attempts[index], result, reason, nodes))
            progress.done += 1
            progress.failed += reason is not None
            write_tables(out)

        def collect(ref) -> tuple[dict | None, str | None]:
            try:
                result = ray.get(ref)
            except RayError as error:
                text = str(error).strip().splitlines()
                return None, f'{type(error).__name__}: {text[-1] if text else ""}'.strip()
            return result, result['reason']

        try:
            while todo or pending:
                while todo and len(pending) < workers:
                    index = todo.popleft()
                    attempts[index] += 1
                    pending[remote.remote(_request(campaign, index, out, token, options.keep))] = index
                ready, _ = ray.wait(list(pending), num_returns=1, timeout=1.0)
                for ref in ready:
                    index = pending.pop(ref)
                    result, reason = collect(ref)
                    if reason is not None and attempts[index] <= retries:
                        progress.note(f'{campaign.run_name(index)} failed (attempt {attempts[index]} of '
                                      f'{retries + 1}): {reason}; trying again')
                        todo.appendleft(index)
                        continue
                    if reason is not None:
                        progress.note(f'{campaign.run_name(index)} failed after {attempts[index]} attempt(s): '
                                      f'{reason}')
                    finish(index, result, reason)
                    progress.show(len(pending), force=True)
                progress.show(len(pending))
        except KeyboardInterrupt:
            interrupted = True
            progress.note(f'sweep {campaign.name}: interrupted; stopping {len(pending)} run(s) under way '
                          '(Ctrl-C again to kill them)')
            for ref in pending:
                ray.cancel(ref)
            try:
                ready, _ = ray.wait(list(pending), num_returns=len(pending), timeout=STOP_TIMEOUT + 30.0)
            except KeyboardInterrupt:
                for ref in pending:
                    ray.cancel(ref, force=True)
                ready = []
            for ref in ready:
                index = pending.pop(ref)
                with contextlib.suppress(TaskCancelledError, RayError):
                    result = ray.get(ref)
                    if result['reason'] is None:
                        finish(index, result, None)
    return interrupted


def check_address(address: str, timeout: float = 5.0) -> None:
    """Raise :class:`SweepError` if nothing listens at a ``HOST:PORT`` address (Ray would retry for minutes);
    other forms (``auto``, ``ray://...``) are left to Ray.
    """
    host, colon, port = address.rpartition(':')
    if not colon or not port.isdigit() or '/' in address:
        return
    try:
        socket.create_connection((host or 'localhost', int(port)), timeout=timeout).close()
    except OSError as error:
        raise SweepError(f'cannot connect to the Ray cluster at {address}: {error.strerror or error}') from None


def sweep(campaign: Campaign, options: SweepOptions) -> int:
    """Run the campaign's missing runs; return 0 if every run succeeded, 1 if one failed, 130 on Ctrl-C."""
    out = options.out
    if options.address is not None:
        check_address(options.address)
    token = _prepare(campaign, options)
    retries = campaign.retries if options.retries is None else options.retries
    done = {row['index'] for row in read_rows(out)} if (out / 'rows').is_dir() else set()
    todo = deque(i for i in range(campaign.size) if i not in done)
    progress = Progress(campaign.name, campaign.size, len(done))
    progress.failed = sum(1 for row in read_rows(out) if row['status'] != 'ok') if done else 0
    if done:
        progress.note(f'sweep {campaign.name}: {len(done)} of {campaign.size} runs already recorded in {out}; '
                      f'running the {len(todo)} missing')
    interrupted = False
    try:
        if todo:
            interrupted = _run_missing(campaign, options, out, token, retries, todo, progress)
    except KeyboardInterrupt:  # before the runs started (Ray starting)
        interrupted = True
    if progress.interactive:
        print(file=sys.stderr)
    rows = write_tables(out)
    failed = progress.failed
    print(f'sweep {campaign.name}: {rows} of {campaign.size} runs recorded, {rows - failed} ok, {failed} failed'
          + (' (interrupted: --resume runs the rest)' if interrupted else '')
          + f'; results {out / PARQUET} and {out / CSV}; report: tethersim report campaign {out}')
    if interrupted:
        return 130
    return 1 if failed else 0
