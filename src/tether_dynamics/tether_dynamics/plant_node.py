"""ROS 2 node ``plant``: the tether between the reel on the platform and the UAV.

A thin wrapper around :class:`tether_dynamics.plant.TetherPlant` (issue-10 plant core,
``plant.step(t, inputs) -> outputs``). Every ``1/state_rate`` of sim time it selects its
inputs by stamp, steps the plant and publishes

* ``/tether/state`` (tether_msgs/TetherState) every step,
* ``/tether/uav_wrench`` (geometry_msgs/WrenchStamped, frame ``world``): force and moment
  of the tether on the UAV, every step,
* ``/truth/relative`` (tether_msgs/RelativePosition, frame ``world``): UAV attachment minus
  guide way, position, velocity and acceleration, every step,
* ``/tether/nodes`` (tether_msgs/TetherNodes) at ``nodes_rate``,
* ``/tether/markers`` (visualization_msgs/MarkerArray, every marker in ``world``, see
  :mod:`tether_dynamics.plant_markers`) at ``markers_rate``.

Inputs: ``/platform/reel_pose`` (geometry_msgs/PoseStamped, the reel mount in ``world``;
the guide way is ``guide_way_offset`` from it in the boat frame); ``/uav/pose``
(geometry_msgs/PoseStamped) when ``uav_source`` is ``topic``; ``/reel/command``
(tether_msgs/ReelCommand, spool-rate or torque) when ``reel_input`` is ``command``. With
``reel_input: reference`` the spool follows the catenary reference length of the true
relative position of the previous step (:class:`tether_dynamics.scripted_reel.ScriptedReel`),
until the smart reel closes that loop.
"""

from __future__ import annotations

import sys

import numpy as np
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.time import Time
from tether_msgs.msg import ReelCommand
from tether_msgs.msg import RelativePosition
from tether_msgs.msg import TetherNodes
from tether_msgs.msg import TetherState
from visualization_msgs.msg import MarkerArray

from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import COMMAND
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.sim_timer import SimTimer
from tether_dynamics.plant_markers import scene_markers
from tether_dynamics.plant_params import PARAMETERS
from tether_dynamics.scripted_reel import ScriptedReel


def _divisor(params: dict, name: str) -> int:
    """Plant steps between two messages of a lower-rate topic; the rate must divide state_rate."""
    ratio = params['state_rate'] / params[name]
    steps = round(ratio)
    if steps < 1 or abs(ratio - steps) > 1e-9 * ratio:
        raise ConfigurationError(f'{name} = {params[name]:g} Hz must divide state_rate = '
                                 f'{params["state_rate"]:g} Hz')
    return steps


def _stamp_ns(msg) -> int:
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


class StampedInput:
    """Messages of one input topic by stamp; the latest not newer than a tick is used for it."""

    def __init__(self) -> None:
        self._messages: list[tuple[int, object]] = []

    def add(self, msg) -> None:
        """Keep ``msg`` in stamp order."""
        stamp = _stamp_ns(msg)
        i = len(self._messages)
        while i > 0 and self._messages[i - 1][0] > stamp:
            i -= 1
        self._messages.insert(i, (stamp, msg))

    def at(self, tick_ns: int):
        """Return the latest message stamped at or before ``tick_ns`` (older ones are dropped), or None."""
        chosen = None
        keep = 0
        for i, (stamp, msg) in enumerate(self._messages):
            if stamp > tick_ns:
                break
            chosen, keep = msg, i
        del self._messages[:keep]
        return chosen


def _vector(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


class PlantNode(Node):
    """Steps the tether plant on stamped inputs and publishes its state, wrench, truth and markers."""

    def __init__(self) -> None:
        super().__init__('plant')
        try:
            self.params = declare_parameters(self, PARAMETERS)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        p = self.params
        self.nodes_every = _divisor(p, 'nodes_rate')
        self.markers_every = _divisor(p, 'markers_rate')
        self.offset = np.asarray(p['guide_way_offset'], dtype=float)
        self.plant = None
        self.steps = 0
        self.scripted = ScriptedReel(p['reference_gain']) if p['reel_input'] == 'reference' else None
        self.last_output = None
        self.reel_pose = StampedInput()
        self.uav_pose = StampedInput()
        self.reel_command = StampedInput()
        self.create_subscription(PoseStamped, '/platform/reel_pose', self.reel_pose.add, STATE)
        if p['uav_source'] == 'topic':
            self.create_subscription(PoseStamped, '/uav/pose', self.uav_pose.add, SENSOR)
        if p['reel_input'] == 'command':
            self.create_subscription(ReelCommand, '/reel/command', self.reel_command.add, COMMAND)
        self.state_pub = self.create_publisher(TetherState, '/tether/state', STATE)
        self.wrench_pub = self.create_publisher(WrenchStamped, '/tether/uav_wrench', STATE)
        self.truth_pub = self.create_publisher(RelativePosition, '/truth/relative', STATE)
        self.nodes_pub = self.create_publisher(TetherNodes, '/tether/nodes', SENSOR)
        self.markers_pub = self.create_publisher(MarkerArray, '/tether/markers', STATE)
        self.timer = SimTimer(self, 1.0 / p['state_rate'], self.step_callback)
        self.get_logger().info(
            f'tether plant: {p["fidelity"]}, {p["elements"]} elements, effects {p["effects"] or "none"}, '
            f'{p["state_rate"]:g} Hz; reel input {p["reel_input"]}; UAV {p["uav_source"]}')

    def step_callback(self, tick: Time) -> None:
        """Step the plant to the tick's sim time and publish its outputs."""
        tick_ns = tick.nanoseconds
        mount = self.reel_pose.at(tick_ns)
        if mount is None:
            return
        raise NotImplementedError


def main(args=None):
    """Run the plant node."""
    sys.exit(run_node(PlantNode, args))


if __name__ == '__main__':
    main()
