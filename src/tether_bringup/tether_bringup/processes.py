"""Child processes of a run: started in their own process group, logged to a file, reaped
with their resource usage (CPU time, peak RSS), and never left behind.

Each child asks the kernel to send it SIGTERM when the bringup dies (``PR_SET_PDEATHSIG``),
so even a SIGKILL of the bringup leaves no node running.
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import time
from collections import deque
from pathlib import Path

_PR_SET_PDEATHSIG = 1
_CLOCK_TICKS = os.sysconf('SC_CLK_TCK')


def _die_with_parent() -> None:
    """In the child before it runs its program: SIGTERM when the bringup dies, and SIGINT and SIGTERM
    acted on whatever the bringup inherited (a parent that ignores SIGINT, as a shell does for a
    background job or a Ray worker does, would otherwise leave the node deaf to being stopped).
    """
    ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, (signal.SIGINT, signal.SIGTERM))


class ChildProcess:
    """One node process of a run."""

    def __init__(self, name: str, command: list[str], log_path: Path, env: dict[str, str],
                 members: tuple[str, ...] = (), pass_fds: tuple[int, ...] = ()) -> None:
        self.name = name
        self.members = members or (name,)
        """The nodes the process runs (the node group runs several)."""
        self.command = command
        self.log_path = log_path
        log_path.parent.mkdir(parents=True, exist_ok=True)
        self._log = open(log_path, 'wb')
        self._popen = subprocess.Popen(
            command, stdin=subprocess.DEVNULL, stdout=self._log, stderr=subprocess.STDOUT,
            env=env, process_group=0, preexec_fn=_die_with_parent, pass_fds=pass_fds)
        self.pid = self._popen.pid
        self.returncode: int | None = None
        self.cpu_time = 0.0
        self.peak_rss = 0
        self.stop_requested = False

    def poll(self) -> int | None:
        """Reap the process if it has exited; return its exit status or None."""
        if self.returncode is None:
            pid, status, usage = os.wait4(self.pid, os.WNOHANG)
            if pid:
                self._reaped(status, usage)
        return self.returncode

    def wait(self, timeout: float) -> bool:
        """Wait up to ``timeout`` seconds for the process to exit; True if it did."""
        deadline = time.monotonic() + timeout
        while self.poll() is None:
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.02)
        return True

    def signal(self, signum: int) -> None:
        """Send ``signum`` to the process group of the child."""
        if self.returncode is None:
            try:
                os.killpg(self.pid, signum)
            except ProcessLookupError:
                pass

    def stop(self, timeout: float = 10.0) -> None:
        """Interrupt the child like Ctrl-C would; kill its group if it does not exit in time."""
        self.stop_requested = True
        self.signal(signal.SIGINT)
        if not self.wait(timeout):
            self.signal(signal.SIGKILL)
            self.wait(5.0)
        self._log.close()

    def cpu_now(self, main_thread: bool = False) -> float | None:
        """CPU seconds (user + system) the running child (or its main thread) has used so far, from ``/proc``;
        None once it has exited.
        """
        path = f'/proc/{self.pid}/task/{self.pid}/stat' if main_thread else f'/proc/{self.pid}/stat'
        try:
            fields = Path(path).read_text().rpartition(')')[2].split()
        except OSError:
            return None
        return (int(fields[11]) + int(fields[12])) / _CLOCK_TICKS

    def tail(self, lines: int = 10) -> list[str]:
        """Return the last ``lines`` lines of the child's log."""
        try:
            with open(self.log_path, errors='replace') as log:
                return [line.rstrip('\n') for line in deque(log, maxlen=lines)]
        except OSError:
            return []

    def _reaped(self, status: int, usage) -> None:
        self.returncode = os.waitstatus_to_exitcode(status)
        self._popen.returncode = self.returncode
        self.cpu_time = usage.ru_utime + usage.ru_stime
        self.peak_rss = usage.ru_maxrss * 1024
