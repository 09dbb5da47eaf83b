"""Helpers of the cross-package tests: run the tethersim command line in a subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from contextlib import contextmanager
from pathlib import Path

import psutil
import yaml
from mcap.reader import make_reader
from rclpy.serialization import deserialize_message

from tether_bringup.scene import find_scene
from tether_common.message_types import message_class

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / 'test' / 'scenes'


def installed_scene(name: str) -> dict:
    """The installed scene ``name`` as the mapping a test edits before :func:`write_scene`."""
    return yaml.safe_load(find_scene(name).read_text())


def write_scene(scene: dict, path: Path) -> str:
    """Write ``scene`` to the YAML file ``path``; return the path, as ``tethersim run`` takes it."""
    path.write_text(yaml.safe_dump(scene))
    return str(path)


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


def _bag_messages(run_dir: Path) -> dict[str, tuple[str, list[tuple[bytes, int]]]]:
    """Per topic of a run's bag, its schema name and the serialized messages in the order received, with log times."""
    topics: dict[str, tuple[str, list[tuple[bytes, int]]]] = {}
    with open(run_dir / 'bag' / 'bag_0.mcap', 'rb') as stream:
        for schema, channel, message in make_reader(stream).iter_messages(log_time_order=False):
            topics.setdefault(channel.topic, (schema.name, []))[1].append((message.data, message.log_time))
    return topics


def bag_payloads(run_dir: Path) -> dict[str, list[tuple[bytes, int]]]:
    """Per topic of a run's bag, the serialized messages in the order the recorder received them, with log times."""
    return {topic: messages for topic, (_, messages) in _bag_messages(run_dir).items()}


def differing_topics(run_a: Path, run_b: Path, normalise: dict | None = None, prefix: bool = False) -> list[str]:
    """Topics of two runs' bags whose messages differ in number, order, log time or content, each with where.

    Each entry is the topic followed by where it first differs (the message's index and log
    time, or the counts), so a failing comparison says when the runs parted. Messages are
    compared as bytes first; a pair whose bytes differ is decoded and compared as
    :func:`bag_contents` compares (the CDR padding the serializer leaves uninitialized can
    differ between equal messages), after ``normalise[topic](text)`` where given. Decoding only
    those pairs keeps the check fast on long bags. With ``prefix`` ``run_b`` is a shorter run
    of the same scene: each of its topics must be the start of ``run_a``'s.
    """
    first, second = _bag_messages(run_a), _bag_messages(run_b)
    differing = [f'{topic}: only in {run_a.name if topic in first else run_b.name}'
                 for topic in sorted(set(first) ^ set(second))]
    for topic in sorted(set(first) & set(second)):
        kind = message_class(first[topic][0])
        same = (normalise or {}).get(topic, lambda text: text)
        a, b = first[topic][1], second[topic][1]
        if prefix:
            a = a[:len(b)]
        for index, ((da, ta), (db, tb)) in enumerate(zip(a, b)):
            if ta != tb or (da != db and same(repr(deserialize_message(da, kind)))
                            != same(repr(deserialize_message(db, kind)))):
                differing.append(f'{topic}: from message {index} (log times {ta / 1e9:.3f} s, {tb / 1e9:.3f} s)')
                break
        else:
            if len(a) != len(b):
                differing.append(f'{topic}: {len(a)} messages against {len(b)}')
    return differing


def bag_contents(run_dir: Path) -> dict[str, list[tuple[str, int]]]:
    """Per topic of a run's bag, each message's full content as text, in the order received, with log times.

    The text is the decoded message's ``repr``: every field, floats written so that they read
    back to the same double (``-0.0`` and ``0.0`` differ). Byte comparison would also compare
    CDR alignment padding (e.g. the 4 bytes between a sequence's length and its first float64),
    which the serializer leaves uninitialized: equal messages can differ there.
    """
    topics: dict[str, list[tuple[str, int]]] = {}
    with open(run_dir / 'bag' / 'bag_0.mcap', 'rb') as stream:
        for schema, channel, message in make_reader(stream).iter_messages(log_time_order=False):
            decoded = deserialize_message(message.data, message_class(schema.name))
            topics.setdefault(channel.topic, []).append((repr(decoded), message.log_time))
    return topics


@contextmanager
def busy_cores():
    """Keep every core busy while the block runs: one seeded pseudo-random busy loop per core."""
    burners = [subprocess.Popen([sys.executable, '-c', f'import random\nrandom.seed({k})\n'
                                 'while True:\n    random.random()'])
               for k in range(os.cpu_count() or 2)]
    try:
        yield
    finally:
        for burner in burners:
            burner.kill()
            burner.wait()
