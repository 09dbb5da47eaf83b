"""A real ArduCopter SITL for the bridge's tests, one private instance per test.

The binary is ``$ARDUPILOT_SITL_BIN`` or ``<repo>/../shared/sitl/arducopter`` (how to build
one is in the README); ``copter.parm`` beside it gives the defaults. Each test takes a free
instance number ``-I N`` (TCP 5760 + 10 N), held with a lock file for the test's duration so
concurrent test runs never share ports, and runs SITL in its own temporary directory with
:class:`uav_bridge.sitl.runner.SitlRunner`.
"""

from __future__ import annotations

import fcntl
import os
import socket
import subprocess
import time
from pathlib import Path

import psutil

from uav_bridge.json_physics.protocol import physics_port
from uav_bridge.sitl.runner import SitlConfig
from uav_bridge.sitl.runner import SitlRunner

ROOT = Path(__file__).resolve().parent.parent


def sitl_binary() -> Path:
    """The ArduCopter SITL binary the tests use."""
    return Path(os.environ.get('ARDUPILOT_SITL_BIN') or ROOT.parent / 'shared' / 'sitl' / 'arducopter')


def sitl_unavailable() -> str | None:
    """Why no SITL can run here, or None when the binary runs."""
    binary = sitl_binary()
    if not binary.is_file():
        return f'no ArduCopter SITL binary at {binary} (set ARDUPILOT_SITL_BIN)'
    try:
        out = subprocess.run([str(binary), '--help'], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired) as error:
        return f'{binary} does not run: {error}'
    if '--instance' not in out.stdout + out.stderr:
        return f'{binary} does not look like an ArduPilot SITL binary'
    return None


def _port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            sock.bind(('0.0.0.0', port))
        except OSError:
            return False
    return True


def _udp_port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        try:
            sock.bind(('127.0.0.1', port))
        except OSError:
            return False
    return True


def connect_when_listening(port: int, timeout: float = 60.0) -> socket.socket:
    """A TCP client on SITL's ``port`` once SITL listens there (it starts listening some time after its start)."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            return socket.create_connection(('127.0.0.1', port), timeout=5.0)
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.2)


def claim_instance() -> tuple[int, object]:
    """A free SITL instance (its TCP ports and JSON physics port free) and the lock file holding it."""
    for instance in range(1, 60):
        handle = open(f'/tmp/tethersim-sitl-instance-{instance}.lock', 'w')   # noqa: SIM115 - held open
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        base = 5760 + 10 * instance
        if all(_port_free(port) for port in (base, base + 2, base + 3)) and _udp_port_free(physics_port(instance)):
            return instance, handle
        handle.close()
    raise RuntimeError('no free SITL instance (ports 5770-6350 busy)')


class SitlProcess(SitlRunner):
    """A SITL runner on a free instance, released by :meth:`close`."""

    def __init__(self, workdir: Path, speedup: float = 10.0, model: str = '+', parameters: tuple = ()) -> None:
        self._lock_file = None
        instance = self._claim_instance()
        binary = sitl_binary()
        defaults = Path(os.environ.get('ARDUPILOT_SITL_DEFAULTS') or binary.parent / 'copter.parm')
        super().__init__(SitlConfig(binary, defaults, workdir, instance=instance, speedup=speedup, model=model,
                                    parameters=parameters))

    def _claim_instance(self) -> int:
        instance, self._lock_file = claim_instance()
        return instance

    def url(self) -> str:
        """The bridge's URL for this instance."""
        return f'tcp:127.0.0.1:{self.config.port}'

    def leftovers(self) -> list[psutil.Process]:
        """SITL processes still running in this instance's working directory."""
        found = []
        for process in psutil.process_iter(['cwd', 'exe']):
            try:
                if process.info['cwd'] == str(self.config.workdir) and 'arducopter' in (process.info['exe'] or ''):
                    found.append(process)
            except (psutil.NoSuchProcess, psutil.AccessDenied):
                continue
        return found

    def kill(self) -> None:
        """Kill SITL (the test's link-loss event)."""
        self.stop()

    def close(self) -> None:
        """Kill SITL and release the instance."""
        self.stop()
        if self._lock_file is not None:
            self._lock_file.close()
            self._lock_file = None


def put_on_instance(scene: dict, instance: int, workdir: Path) -> dict:
    """A scene's SITL nodes moved onto SITL ``instance`` (its ports), SITL running in ``workdir``: the ``sitl``
    node, the ``json_physics`` node if the scene has one and the ``mavlink_bridge``'s URL.
    """
    nodes = scene['nodes']
    nodes['sitl']['parameters'].update(instance=instance, workdir=str(workdir))
    if 'json_physics' in nodes:
        nodes['json_physics']['parameters']['instance'] = instance
    nodes['mavlink_bridge']['parameters']['url'] = f'tcp:127.0.0.1:{5760 + 10 * instance}'
    return scene
