"""ROS 2 node ``sitl``: runs a real ArduCopter SITL for the scene, for as long as the node runs.

A thin wrapper around :class:`uav_bridge.sitl.runner.SitlRunner`, so a scene can start the
autopilot the ``mavlink_bridge`` node connects to. SITL runs in wall time at ``speedup``; it
waits for the bridge to connect before it runs. If SITL ends on its own the node logs SITL's
last lines, then the cause in one line (``SITL exited with status -9 (killed by SIGKILL)``),
and exits with status 1, without a traceback: while the run goes on, the bringup then ends it
naming the node and that cause; when SITL died so close to the run's end that the bringup was
already stopping the node, the node finds it at its end and exits with status 1 all the same,
which fails the run too. When the node ends, SITL is killed, and its working directory is
removed unless the scene gave one (``workdir``: kept, e.g. under the run directory). The
scene's ``parameters`` are confirmed on SITL's second MAVLink port once it runs
(:mod:`uav_bridge.sitl.parameter_check`): a name SITL does not have, or a value it does not
hold, ends the node the same way, naming them, since SITL itself skips an unknown name in its
defaults file without a word.
"""

from __future__ import annotations

import shutil
import signal
import sys
import tempfile
import threading
from pathlib import Path

from rclpy.node import Node

from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.ros_parameters import declare_parameters
from uav_bridge.sitl.parameter_check import CheckResult
from uav_bridge.sitl.parameter_check import check_parameters
from uav_bridge.sitl.params import PARAMETERS
from uav_bridge.sitl.runner import SitlConfig
from uav_bridge.sitl.runner import SitlError
from uav_bridge.sitl.runner import SitlRunner
from uav_bridge.sitl.runner import locate_binary


def parse_parameters(items: list[str]) -> tuple[tuple[str, float], ...]:
    """``NAME=VALUE`` strings as (name, value) pairs; ValueError naming a malformed one."""
    pairs = []
    for item in items:
        name, sep, value = item.partition('=')
        try:
            pairs.append((name.strip(), float(value)))
        except ValueError:
            sep = ''
        if not sep or not name.strip():
            raise ValueError(f'parameter parameters: {item!r} is not NAME=VALUE with a number')
    return tuple(pairs)


class SitlNode(Node):
    """Starts SITL, watches it, kills it at the end."""

    def __init__(self) -> None:
        super().__init__('sitl')
        try:
            params = declare_parameters(self, PARAMETERS)
            binary = locate_binary(params['binary'])
            defaults = Path(params['defaults']) if params['defaults'] else binary.parent / 'copter.parm'
            self.temporary = not params['workdir']
            workdir = Path(params['workdir'] or tempfile.mkdtemp(prefix='tethersim-sitl-'))
            self.runner = SitlRunner(SitlConfig(binary, defaults, workdir, instance=params['instance'],
                                                speedup=params['speedup'], model=params['model'],
                                                home=params['home'], parameters=parse_parameters(params['parameters'])))
        except (SitlError, ValueError) as error:
            raise ConfigurationError(str(error)) from None
        self.runner.start()
        self.failure = ''
        self.check: CheckResult | None = None
        self._stop_check = threading.Event()
        wanted = dict(self.runner.config.parameters_used)
        if wanted:
            url = f'tcp:127.0.0.1:{self.runner.config.port + 2}'
            threading.Thread(target=self._check, args=(url, wanted), name='parameter-check', daemon=True).start()
        self.create_timer(0.5, self.watch)
        self.get_logger().info(f'SITL started: {" ".join(self.runner.command())} in {workdir} '
                               f'(MAVLink on tcp:127.0.0.1:{self.runner.config.port})')

    def _check(self, url: str, wanted: dict) -> None:
        self.check = check_parameters(url, wanted, stop=self._stop_check)

    def watch(self) -> None:
        """End the node when SITL ended on its own."""
        if self.failure:
            return
        if self.runner.exit_status() is not None:
            self._fail(self._exited())
            return
        check, self.check = self.check, None
        if check is not None and check.problem():
            self._fail(f'parameters: {check.problem()}')
            return
        if check is not None:
            self.get_logger().info('SITL holds the scene\'s parameters: '
                                   + ', '.join(f'{name} = {value:g}' for name, value in check.confirmed.items()))

    def _exited(self) -> str:
        """The cause of SITL's end in one line, after its last lines in the log."""
        status = self.runner.exit_status()
        tail = self.runner.log_tail()
        if tail:
            self.get_logger().info('SITL\'s last lines:\n' + tail)
        how = f' (killed by {signal.Signals(-status).name})' if status is not None and status < 0 else ''
        sim = self.get_clock().now().nanoseconds * 1e-9
        return f'SITL exited with status {status}{how} at sim time {sim:.2f} s: the autopilot is gone'

    def _fail(self, cause: str) -> None:
        """Log the cause as the node's last line and end the node; :func:`main` exits with status 1."""
        self.failure = cause
        self.get_logger().error(cause)
        self.context.try_shutdown()

    def destroy_node(self) -> None:
        """Stop the parameter check, kill SITL with the node (a SITL already dead fails the node), remove a
        temporary working directory.
        """
        self._stop_check.set()
        if not self.failure and self.runner.exit_status() is not None:
            self.failure = self._exited()
            self.get_logger().error(f'{self.failure} (found at the end of the run)')
        self.runner.stop()
        if self.temporary:
            shutil.rmtree(self.runner.config.workdir, ignore_errors=True)
        super().destroy_node()


def main(args=None):
    """Run the SITL node: exit status 1 when SITL ended on its own (or its parameters are not held)."""
    built: list[SitlNode] = []

    def build() -> SitlNode:
        built.append(SitlNode())
        return built[0]
    status = run_node(build, args)
    sys.exit(status or (1 if built and built[0].failure else 0))


if __name__ == '__main__':
    main()
