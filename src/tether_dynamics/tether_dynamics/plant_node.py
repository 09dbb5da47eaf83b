"""ROS 2 node ``plant``: the tether between the reel on the platform and the UAV.

A thin wrapper around :class:`tether_dynamics.plant.TetherPlant` (issue-10 plant core,
``plant.step(t, inputs) -> outputs``). Every ``1/state_rate`` of sim time, in lockstep
(:mod:`tether_common.lockstep`), it selects its inputs by stamp, steps the plant and publishes

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
(tether_msgs/ReelCommand: spool rate, torque or payout rate, ``reel_drive``) when
``reel_input`` is ``command``. The platform and UAV inputs are taken at the tick's own
stamp (delay 0; they are the plant's upstream); the reel command with a delay of one reel
period (``reel_command_rate``): the command stamped t is the reel's drive over
[t, t + period], which the plant applies in its step ending at t + period, the explicit
one-step delay of the loop reel command → plant → tether state → reel. With
``reel_input: reference`` the spool follows the catenary reference length of the true
relative position of the previous step (:class:`tether_dynamics.scripted_reel.ScriptedReel`),
until the smart reel closes that loop.
"""

from __future__ import annotations

import sys

import numpy as np
from geometry_msgs.msg import Point
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from geometry_msgs.msg import Vector3
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from tether_msgs.msg import ReelCommand
from tether_msgs.msg import RelativePosition
from tether_msgs.msg import TetherNodes
from tether_msgs.msg import TetherState
from visualization_msgs.msg import MarkerArray

from tether_common.geometry_fill import fill_vector
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import LOOP
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.rotation import quaternion_rotation
from tether_common.geometry_fill import fill_xyz
from tether_dynamics.plant import PlantConfig
from tether_dynamics.plant import PlantConfigError
from tether_dynamics.plant import PlantDivergenceError
from tether_dynamics.plant import PlantInputs
from tether_dynamics.plant import PlantOutputs
from tether_dynamics.plant import PlantStepError
from tether_dynamics.plant import ReelConfig
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant import UavConfig
from tether_dynamics.plant.ends import point_on_body
from tether_dynamics.plant.plant import warm_up
from tether_dynamics.plant_markers import SceneMarkers
from tether_dynamics.plant_params import PARAMETERS
from tether_dynamics.scripted_reel import ScriptedReel
from tether_dynamics.statics.catenary import GRAVITY
from tether_dynamics.statics.reference_length import reference_length


REEL_CONTROLS = {'spool_rate': ReelCommand.CONTROL_SPOOL_RATE, 'torque': ReelCommand.CONTROL_TORQUE,
                 'payout_rate': ReelCommand.CONTROL_PAYOUT_RATE}
REEL_FIELDS = {'spool_rate': 'spool_rate', 'torque': 'spool_torque', 'payout_rate': 'payout_rate'}


def _divisor(params: dict, name: str) -> int:
    """Plant steps between two messages of a lower-rate topic; the rate must divide state_rate."""
    ratio = params['state_rate'] / params[name]
    steps = round(ratio)
    if steps < 1 or abs(ratio - steps) > 1e-9 * ratio:
        raise ConfigurationError(f'{name} = {params[name]:g} Hz must divide state_rate = '
                                 f'{params["state_rate"]:g} Hz')
    return steps


def _vector(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


def _quaternion(q) -> np.ndarray:
    return np.array([q.x, q.y, q.z, q.w])


def _rigid_motion(pose, twist) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """Position, quaternion (x, y, z, w), velocity and angular velocity from a pose and twist pair, or None."""
    if pose is None or twist is None:
        return None
    return (_vector(pose.pose.position), _quaternion(pose.pose.orientation),
            _vector(twist.twist.linear), _vector(twist.twist.angular))


def plant_config(params: dict, initial_length: float) -> PlantConfig:
    """The plant's configuration from the node's parameters (see :mod:`tether_dynamics.plant_params`)."""
    p = params
    drive = 'torque' if p['reel_input'] == 'command' and p['reel_drive'] == 'torque' else 'spool_rate'
    attach = (0.0, 0.0, 0.0) if p['uav_source'] == 'fixed' else tuple(p['uav_attach_offset'])
    return PlantConfig(
        fidelity=p['fidelity'], elements=p['elements'], dt=p['integration_step'], effects=tuple(p['effects']),
        mass_per_length=p['linear_density'], ea=p['axial_stiffness'], diameter=p['diameter'],
        drag_coefficient=p['drag_coefficient'], damping=p['damping'], wind=tuple(p['wind']),
        gravity=GRAVITY, guide_way_offset=tuple(p['guide_way_offset']), initial_length=initial_length,
        reel=ReelConfig(input=drive, spool_radius=p['spool_radius'], inertia=p['spool_inertia'],
                        viscous_friction=p['spool_friction'], total_length=p['reel_capacity'],
                        max_length=p['reel_capacity']),
        uav=UavConfig(mode='prescribed', attach_offset=attach))


class PlantNode(Node):
    """Steps the tether plant on stamped inputs and publishes its state, wrench, truth and markers."""

    def __init__(self, **options) -> None:
        super().__init__('plant', **options)
        try:
            self.params = declare_parameters(self, PARAMETERS)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        p = self.params
        self.nodes_every = _divisor(p, 'nodes_rate')
        self.markers_every = _divisor(p, 'markers_rate')
        self.offset = np.asarray(p['guide_way_offset'], dtype=float)
        self.plant = self._build(p['initial_length']) if p['initial_length'] > 0.0 else None
        self._warm_up()
        self.started = False
        self.steps = 0
        self.scripted = ScriptedReel(p['reference_gain']) if p['reel_input'] == 'reference' else None
        self.truth: tuple[float, np.ndarray, np.ndarray] | None = None
        self.deployed = 0.0
        self.command = 0.0
        platform_period = 1.0 / p['platform_rate']
        inputs = [Input('/platform/reel_pose', PoseStamped, platform_period, 0.0, STATE),
                  Input('/platform/reel_twist', TwistStamped, platform_period, 0.0, STATE)]
        if p['uav_source'] == 'topic':
            inputs += [Input('/uav/pose', PoseStamped, 1.0 / p['uav_rate'], 0.0, SENSOR),
                       Input('/uav/twist', TwistStamped, 1.0 / p['uav_rate'], 0.0, SENSOR)]
        if p['reel_input'] == 'command':
            command_period = 1.0 / p['reel_command_rate']
            inputs.append(Input('/reel/command', ReelCommand, command_period, command_period, LOOP))
        self.state_pub = self.create_publisher(TetherState, '/tether/state', STATE)
        self.wrench_pub = self.create_publisher(WrenchStamped, '/tether/uav_wrench', STATE)
        self.truth_pub = self.create_publisher(RelativePosition, '/truth/relative', STATE)
        self.nodes_pub = self.create_publisher(TetherNodes, '/tether/nodes', SENSOR)
        self.markers_pub = self.create_publisher(MarkerArray, '/tether/markers', STATE)
        self.markers = SceneMarkers()
        # One message object per per-step topic, refilled each step: publish() serialises it
        # at once, and building a message's nested fields anew costs more than the plant step.
        self.state_msg = TetherState()
        self.wrench_msg = WrenchStamped()
        self.truth_msg = RelativePosition()
        self.nodes_msg = TetherNodes()
        for msg in (self.state_msg, self.wrench_msg, self.truth_msg, self.nodes_msg):
            msg.header.frame_id = 'world'
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / p['state_rate'], self.step_callback, inputs)
        self.get_logger().info(
            f'tether plant: {p["fidelity"]}, {p["elements"]} elements, effects {p["effects"] or "none"}, '
            f'{p["state_rate"]:g} Hz; reel input {p["reel_input"]}; UAV {p["uav_source"]}')

    def _inputs(self, tick: Tick) -> PlantInputs | None:
        """The plant's inputs for the tick from the messages the lockstep selected, or None before the first."""
        platform = _rigid_motion(tick.inputs['/platform/reel_pose'], tick.inputs['/platform/reel_twist'])
        if platform is None:
            return None
        inputs = PlantInputs(sea_surface_height=self.params['sea_level'])
        (inputs.platform_position, inputs.platform_quaternion,
         inputs.platform_velocity, inputs.platform_angular_velocity) = platform
        if self.params['uav_source'] == 'fixed':
            inputs.uav_position = np.asarray(self.params['uav_position'], dtype=float)
            return inputs
        uav = _rigid_motion(tick.inputs['/uav/pose'], tick.inputs['/uav/twist'])
        if uav is None:
            return None
        inputs.uav_position, inputs.uav_quaternion, inputs.uav_velocity, inputs.uav_angular_velocity = uav
        return inputs

    def _reel(self, tick: Tick, inputs: PlantInputs) -> None:
        """Set the reel input for the tick: the scripted reel, or the latest /reel/command (held; 0 before the first)."""
        if self.scripted is not None:
            if self.truth is not None:
                payout = self.scripted.step(self.truth[0], self.truth[1], self.deployed)
                inputs.spool_rate = payout / self.params['spool_radius']
            return
        command = tick.inputs['/reel/command']
        drive = self.params['reel_drive']
        if command is not None:
            if command.control != REEL_CONTROLS[drive]:
                raise ConfigurationError(f'/reel/command with control {command.control} but the plant\'s '
                                         f'reel_drive is {drive} (control {REEL_CONTROLS[drive]})')
            self.command = getattr(command, REEL_FIELDS[drive])
        if drive == 'torque':
            inputs.reel_torque = self.command
        else:
            inputs.spool_rate = self.command / (self.params['spool_radius'] if drive == 'payout_rate' else 1.0)

    def _build(self, initial_length: float) -> TetherPlant:
        """The plant for the scene's parameters; a configuration it refuses ends the node (exit 2)."""
        try:
            return TetherPlant(plant_config(self.params, initial_length))
        except PlantConfigError as error:
            raise ConfigurationError(str(error)) from None

    def _checked_config(self) -> PlantConfig:
        """The plant's configuration at the reel's least length; refused before the first step if the plant
        refuses it (any length: the length is checked then).
        """
        try:
            return plant_config(self.params, ReelConfig().min_length)
        except PlantConfigError as error:
            raise ConfigurationError(str(error)) from None

    def _warm_up(self) -> None:
        """Compile the plant's kernels while the node starts (:func:`~tether_dynamics.plant.plant.warm_up`, a scratch
        plant at the reel's full length); a configuration the plant refuses there ends the node in one line (exit 2).
        """
        config = self._checked_config()
        try:
            warm_up(config)
        except (PlantConfigError, PlantStepError) as error:
            raise ConfigurationError(f'at the reel\'s full length ({config.reel.max_length:g} m): {error}') from None

    def _start(self, inputs: PlantInputs) -> None:
        """At the first step, without an initial_length, deploy the reference length of the first relative position."""
        if self.plant is None:
            guide, _ = self._guide_way(inputs)
            d = inputs.uav_position - guide
            self.plant = self._build(reference_length(float(np.hypot(d[0], d[1])), float(d[2])).length)
        self.started = True

    def _guide_way(self, inputs: PlantInputs) -> tuple[np.ndarray, np.ndarray]:
        rotation = quaternion_rotation(inputs.platform_quaternion, 'the reel pose orientation')
        return point_on_body(inputs.platform_position, rotation, inputs.platform_velocity,
                             inputs.platform_angular_velocity, self.offset)

    def step_callback(self, tick: Tick) -> None:
        """Step the plant to the tick's sim time and publish its outputs."""
        t = tick.seconds
        inputs = self._inputs(tick)
        if inputs is None:
            return
        self._reel(tick, inputs)
        if not self.started:
            self._start(inputs)
        try:
            out = self.plant.step(t, inputs)
        except (PlantStepError, PlantDivergenceError, ValueError) as error:
            self.get_logger().error(f'plant step at t = {t:.3f} s failed: {error}')
            raise SystemExit(1) from None
        self.deployed = out.deployed_length
        stamp = tick.stamp
        self._publish_state(stamp, out)
        self._publish_wrench(stamp, out)
        self._publish_truth(stamp, t, out)
        if self.steps % self.nodes_every == 0:
            self._publish_nodes(stamp, out)
        if self.steps % self.markers_every == 0:
            self.markers_pub.publish(self.markers.fill(stamp, out.nodes, inputs.platform_position,
                                                       inputs.platform_quaternion, out.reel_end, out.uav_end,
                                                       out.lowest_point, out.fouling))
        self.steps += 1

    def _publish_state(self, stamp, out: PlantOutputs) -> None:
        msg = self.state_msg
        msg.header.stamp = stamp
        msg.fidelity = out.fidelity
        msg.element_count = out.element_count if out.fidelity != 'quasi_static' else 0
        fill_vector(msg.reel_end, out.reel_end)
        fill_vector(msg.uav_end, out.uav_end)
        fill_vector(msg.lowest_point, out.lowest_point)
        msg.deployed_length = out.deployed_length
        msg.tension_reel, msg.tension_uav = out.tension_reel, out.tension_uav
        msg.departure_angle, msg.arrival_angle = out.departure_angle, out.arrival_angle
        msg.max_strain = out.max_strain
        fill_vector(msg.force_on_reel, out.force_on_reel)
        fill_vector(msg.force_on_uav, out.force_on_uav)
        fill_vector(msg.moment_on_uav, out.moment_on_uav)
        msg.payout_rate, msg.spool_angle, msg.spool_rate = out.payout_rate, out.spool_angle, out.spool_rate
        msg.reel_work = out.reel_work
        msg.clearance_deck, msg.clearance_sea, msg.fouling = out.clearance_deck, out.clearance_sea, out.fouling
        msg.kinetic_energy, msg.potential_energy = out.kinetic_energy, out.potential_energy
        msg.strain_energy = out.strain_energy
        self.state_pub.publish(msg)

    def _publish_wrench(self, stamp, out: PlantOutputs) -> None:
        msg = self.wrench_msg
        msg.header.stamp = stamp
        fill_vector(msg.wrench.force, out.force_on_uav)
        fill_vector(msg.wrench.torque, out.moment_on_uav)
        self.wrench_pub.publish(msg)

    def _publish_truth(self, stamp, t: float, out: PlantOutputs) -> None:
        """UAV attachment minus guide way; velocities exact, acceleration a backward difference over one step."""
        position = out.uav_end - out.reel_end
        velocity = out.uav_end_velocity - out.reel_end_velocity
        acceleration = np.zeros(3)
        if self.truth is not None and t > self.truth[0]:
            acceleration = (velocity - self.truth[2]) / (t - self.truth[0])
        self.truth = (t, position, velocity)
        msg = self.truth_msg
        msg.header.stamp = stamp
        fill_vector(msg.position, position)
        fill_vector(msg.velocity, velocity)
        fill_vector(msg.acceleration, acceleration)
        self.truth_pub.publish(msg)

    def _publish_nodes(self, stamp, out: PlantOutputs) -> None:
        msg = self.nodes_msg
        msg.header.stamp = stamp
        fill_xyz(msg.positions, out.nodes, Point)
        fill_xyz(msg.velocities, out.velocities, Vector3)
        msg.tensions = out.tensions.tolist()
        msg.arc_length = out.arc_length.tolist()
        self.nodes_pub.publish(msg)


def main(args=None):
    """Run the plant node."""
    sys.exit(run_node(PlantNode, args))


if __name__ == '__main__':
    main()
