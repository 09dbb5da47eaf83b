"""Run a real ArduPilot SITL binary as a child program (no rclpy).

ArduPilot is GPL-3.0: the project only starts the binary the user built (see the README);
no ArduPilot code is part of it. :class:`SitlRunner` starts ``arducopter --model + --speedup S
--defaults copter.parm -I N`` in its own working directory (SITL writes ``eeprom.bin``,
``logs/`` and ``terrain/`` there), in its own process group, with ``PR_SET_PDEATHSIG`` so
it dies with its parent, and kills the whole group on :meth:`SitlRunner.stop`. SITL serves
MAVLink on TCP 5760 + 10 N and runs only once a client connected there.
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path

PR_SET_PDEATHSIG = 1


class SitlError(Exception):
    """The SITL binary or its defaults cannot be used."""


@dataclass(frozen=True)
class SitlConfig:
    """How to run SITL."""

    binary: Path
    defaults: Path
    workdir: Path
    instance: int = 0
    speedup: float = 1.0
    model: str = '+'
    home: str = ''                  # lat,lng,alt,yaw; empty: SITL's default (Canberra model field)
    wipe: bool = True               # start from default parameters (-w)
    parameters: tuple = ()          # (name, value) pairs overriding the defaults file

    @property
    def lockstep(self) -> bool:
        """Whether SITL flies an external physics that sets its pace (``--model JSON``)."""
        return self.model.upper().startswith('JSON')

    @property
    def parameters_used(self) -> tuple:
        """``parameters``, and for a lockstep model ``LOG_BACKEND_TYPE 0`` unless they set it.

        SITL's dataflash logger runs in a thread of its own, and with it on the flight depends on
        the machine's load: a pair of flights of the same mission on the JSON physics, SITL in
        lockstep at 100x and at 1x, took two tracks (up to 20 mm apart after 56 s) in both pairs
        of two run at once; with the logger off, both flights of a pair were equal to the bit in
        all 4 pairs of two such double runs. A lockstep run is meant to be the same at any pace,
        so the logger is off unless asked for.
        """
        given = {name.upper() for name, _ in self.parameters}
        if self.lockstep and 'LOG_BACKEND_TYPE' not in given:
            return (*self.parameters, ('LOG_BACKEND_TYPE', 0))
        return self.parameters

    @property
    def defaults_used(self) -> Path:
        """The defaults file SITL reads: ``defaults``, or its copy with the parameters used in the working directory."""
        return self.workdir / 'defaults.parm' if self.parameters_used else self.defaults

    @property
    def port(self) -> int:
        """The TCP port of SITL's first MAVLink serial port."""
        return 5760 + 10 * self.instance


def locate_binary(given: str) -> Path:
    """The SITL binary: ``given``, else ``$ARDUPILOT_SITL_BIN``; SitlError when it is not an executable file."""
    text = given or os.environ.get('ARDUPILOT_SITL_BIN', '')
    if not text:
        raise SitlError('no SITL binary: set the binary parameter or ARDUPILOT_SITL_BIN '
                        '(README: building ArduCopter SITL)')
    path = Path(text).expanduser()
    if not path.is_file() or not os.access(path, os.X_OK):
        raise SitlError(f'SITL binary {path}: not an executable file')
    return path


def _die_with_parent() -> None:
    ctypes.CDLL('libc.so.6', use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


class SitlRunner:
    """One SITL process (see the module docstring)."""

    def __init__(self, config: SitlConfig) -> None:
        if not config.defaults.is_file():
            raise SitlError(f'SITL defaults file {config.defaults}: not found')
        self.config = config
        self.process: subprocess.Popen | None = None
        self.log_path = config.workdir / 'sitl.log'

    def command(self) -> list[str]:
        """The command line that starts SITL."""
        c = self.config
        cmd = [str(c.binary), '--model', c.model, '--speedup', f'{c.speedup:g}', '--defaults', str(c.defaults_used),
               f'-I{c.instance}']
        if c.home:
            cmd += ['--home', c.home]
        return cmd + (['-w'] if c.wipe else [])

    def start(self, wipe: bool | None = None) -> None:
        """Start SITL; ``wipe`` overrides the configured parameter wipe for this start."""
        self.config.workdir.mkdir(parents=True, exist_ok=True)
        self._write_defaults()
        cmd = self.command()
        if wipe is False and '-w' in cmd:
            cmd.remove('-w')
        with open(self.log_path, 'a') as log:
            self.process = subprocess.Popen(cmd, cwd=self.config.workdir, stdout=log, stderr=subprocess.STDOUT,
                                            stdin=subprocess.DEVNULL, start_new_session=True,
                                            preexec_fn=_die_with_parent)

    def _write_defaults(self) -> None:
        """The defaults file with the parameters used in place of (or after) the lines that set them."""
        c = self.config
        if not c.parameters_used:
            return
        override = {name.upper(): value for name, value in c.parameters_used}
        lines = [line for line in c.defaults.read_text().splitlines()
                 if not line.split() or line.split()[0].upper() not in override]
        lines += [f'{name} {value:g}' for name, value in override.items()]
        c.defaults_used.write_text('\n'.join(lines) + '\n')

    def exit_status(self) -> int | None:
        """SITL's exit status once it ended, None while it runs (or before it started)."""
        return None if self.process is None else self.process.poll()

    def log_tail(self, lines: int = 10) -> str:
        """The last lines SITL printed."""
        try:
            return '\n'.join(self.log_path.read_text(errors='replace').splitlines()[-lines:])
        except OSError:
            return ''

    def stop(self) -> None:
        """SIGKILL SITL's process group and reap it (idempotent)."""
        if self.process is None:
            return
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait(timeout=20)
        self.process = None
