"""Start and stop a real ArduCopter SITL for the bridge's tests, one private instance per test.

The binary is ``$ARDUPILOT_SITL_BIN`` or ``<repo>/../shared/sitl/arducopter`` (how to build
one is in the README); ``copter.parm`` beside it gives the defaults. Each run takes a free
instance number ``-I N`` (TCP 5760 + 10 N), held with a lock file for the test's duration so
concurrent test runs never share ports, and its own temporary working directory (SITL writes
``eeprom.bin``, ``logs/`` and ``terrain/`` there). The process dies with the test process
(``PR_SET_PDEATHSIG``) and :meth:`SitlProcess.stop` kills its whole process group.
"""

from __future__ import annotations

import ctypes
import fcntl
import os
import signal
import socket
import subprocess
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parent.parent
PR_SET_PDEATHSIG = 1


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


def _die_with_parent() -> None:
    ctypes.CDLL('libc.so.6', use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


def _port_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            sock.bind(('0.0.0.0', port))
        except OSError:
            return False
    return True


class SitlProcess:
    """One ArduCopter SITL instance (``--model +``) at ``speedup`` times real time."""

    def __init__(self, workdir: Path, speedup: float = 10.0) -> None:
        self.binary = sitl_binary()
        self.defaults = Path(os.environ.get('ARDUPILOT_SITL_DEFAULTS') or self.binary.parent / 'copter.parm')
        self.workdir = workdir
        self.speedup = speedup
        self.process: subprocess.Popen | None = None
        self._lock_file = None
        self.instance = self._claim_instance()
        self.port = 5760 + 10 * self.instance
        self.log_path = workdir / 'sitl.log'

    def _claim_instance(self) -> int:
        for instance in range(1, 60):
            handle = open(f'/tmp/tethersim-sitl-instance-{instance}.lock', 'w')   # noqa: SIM115 - held open
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                handle.close()
                continue
            base = 5760 + 10 * instance
            if all(_port_free(port) for port in (base, base + 2, base + 3)):
                self._lock_file = handle
                return instance
            handle.close()
        raise RuntimeError('no free SITL instance (ports 5770-6350 busy)')

    def url(self) -> str:
        """The bridge's URL for this instance."""
        return f'tcp:127.0.0.1:{self.port}'

    def start(self, wipe: bool = True) -> None:
        """Start SITL (it waits for the bridge to connect before it runs)."""
        cmd = [str(self.binary), '--model', '+', '--speedup', f'{self.speedup:g}', '--defaults', str(self.defaults),
               f'-I{self.instance}'] + (['-w'] if wipe else [])
        with open(self.log_path, 'a') as log:
            self.process = subprocess.Popen(cmd, cwd=self.workdir, stdout=log, stderr=subprocess.STDOUT,
                                            stdin=subprocess.DEVNULL, start_new_session=True,
                                            preexec_fn=_die_with_parent)

    def kill(self) -> None:
        """SIGKILL the SITL process group and reap it."""
        if self.process is None:
            return
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait(timeout=20)
        self.process = None

    def leftovers(self) -> list[psutil.Process]:
        """SITL processes still running in this instance's working directory."""
        found = []
        for process in psutil.process_iter(['cwd', 'exe']):
            try:
                if process.info['cwd'] == str(self.workdir) and 'arducopter' in (process.info['exe'] or ''):
                    found.append(process)
            except (psutil.NoSuchProcess, psutil.AccessDenied):
                continue
        return found

    def close(self) -> None:
        """Kill SITL and release the instance."""
        self.kill()
        if self._lock_file is not None:
            self._lock_file.close()
            self._lock_file = None
