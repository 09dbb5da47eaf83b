"""ROS 2 node ``sitl``: runs a real ArduCopter SITL for the scene, for as long as the node runs.

A thin wrapper around :class:`uav_bridge.sitl_runner.SitlRunner`, so a scene can start the
autopilot the ``mavlink_bridge`` node connects to. SITL runs in wall time at ``speedup``; it
waits for the bridge to connect before it runs. If SITL ends on its own the node logs its
last lines and exits with status 1 (the bringup then ends the run naming the node); when the
node ends, SITL is killed. The scene's ``parameters`` are confirmed on SITL's second MAVLink
port once it runs (:mod:`uav_bridge.sitl_parameter_check`): a name SITL does not have, or a
value it does not hold, ends the node the same way, naming them, since SITL itself skips an
unknown name in its defaults file without a word.
"""

from __future__ import annotations

import sys
import tempfile
import threading
from pathlib import Path

from rclpy.node import Node

from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.ros_parameters import declare_parameters
from uav_bridge.sitl_parameter_check import CheckResult
from uav_bridge.sitl_parameter_check import check_parameters
from uav_bridge.sitl_params import PARAMETERS
from uav_bridge.sitl_runner import SitlConfig
from uav_bridge.sitl_runner import SitlError
from uav_bridge.sitl_runner import SitlRunner
from uav_bridge.sitl_runner import locate_binary


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
            workdir = Path(params['workdir'] or tempfile.mkdtemp(prefix='tethersim-sitl-'))
            self.runner = SitlRunner(SitlConfig(binary, defaults, workdir, instance=params['instance'],
                                                speedup=params['speedup'], model=params['model'],
                                                home=params['home'], parameters=parse_parameters(params['parameters'])))
        except (SitlError, ValueError) as error:
            raise ConfigurationError(str(error)) from None
        self.runner.start()
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
        status = self.runner.exit_status()
        if status is not None:
            self.get_logger().error(f'SITL exited with status {status}; its last lines:\n{self.runner.log_tail()}')
            raise SystemExit(1)
        check, self.check = self.check, None
        if check is not None and check.problem():
            self.get_logger().error(f'parameters: {check.problem()}')
            raise SystemExit(1)
        if check is not None:
            self.get_logger().info('SITL holds the scene\'s parameters: '
                                   + ', '.join(f'{name} = {value:g}' for name, value in check.confirmed.items()))

    def destroy_node(self) -> None:
        """Stop the parameter check and kill SITL with the node."""
        self._stop_check.set()
        self.runner.stop()
        super().destroy_node()


def main(args=None):
    """Run the SITL node."""
    sys.exit(run_node(SitlNode, args))


if __name__ == '__main__':
    main()
