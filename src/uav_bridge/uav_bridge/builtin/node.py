"""ROS 2 node ``builtin_uav``: a UAV for runs without an autopilot, with the bridge's interface.

A thin wrapper around :class:`uav_bridge.builtin.uav.BuiltinUav` (the plant's UAV rigid body
under the cascaded station controller). It publishes what ``mavlink_bridge`` publishes —
``/uav/pose``, ``/uav/twist`` (``world``) at every tick, ``/uav/imu`` (``uav``, FLU) at every
multiple of 1/``imu_rate``, ``/uav/state`` (transient local) at every multiple of
1/``state_rate`` — and everything it
does is fixed by stamps (:mod:`tether_common.lockstep`):

* With ``tether_force: topic`` the tether's force on the UAV comes from the plant on
  ``/tether/uav_wrench`` (geometry_msgs/WrenchStamped, world), a lockstep input with a delay
  of one wrench period: the tick at t integrates the body over [t - period, t] under the
  wrench stamped t - period, the plant's force at the start of the interval, and publishes
  the pose stamped t that the plant's tick t takes with no delay. That delay is the explicit
  one-step delay of the loop UAV pose → plant → wrench → UAV. Before the first wrench the
  force is zero.
* With ``command_rate`` > 0 the mission's ``/uav/command`` (tether_msgs/UavCommand) is a
  lockstep input with a delay of one command period P: the tick at t takes the command
  stamped t − P (the mission's step before), carries out its request once per sequence
  number before integrating, and flies to its setpoint while it holds. The request's outcome
  (``command_sequence``, ``command_success``, ``command_message``) is in the ``/uav/state``
  stamped t (t − P is a mission step, so a multiple of P; with ``state_rate`` = the mission's
  rate, also a state tick). A request of the mission's step s thus takes effect at s + P and
  its answer reaches the mission's step s + P: the loop mission → UAV → mission's one-step delay.

The services ``/uav/set_mode``, ``/uav/arm``, ``/uav/takeoff``, ``/uav/land`` and the topic
``/uav/setpoint`` (geometry_msgs/PoseStamped, ``world``) are served as the bridge serves them,
for calls by hand (``ros2 service call``): they take effect on arrival, between ticks, so a
run driven by them is not reproducible. With ``command_rate`` > 0 ``/uav/setpoint`` is not
subscribed (the mission's setpoint comes in ``/uav/command``).
"""

from __future__ import annotations

import sys

import numpy as np
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from sensor_msgs.msg import Imu
from std_srvs.srv import SetBool
from std_srvs.srv import Trigger
from tether_msgs.msg import UavCommand
from tether_msgs.msg import UavState
from tether_msgs.srv import SetMode
from tether_msgs.srv import Takeoff

from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.lockstep import period_ns
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import COMMAND
from tether_common.qos import LOOP
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.rotation import quaternion_rotation
from uav_bridge.builtin.params import PARAMETERS
from uav_bridge.builtin.uav import BuiltinUav
from uav_bridge.builtin.uav import BuiltinUavConfig
from uav_bridge.ros_fill import fill_pose_and_twist


class BuiltinUavNode(Node):
    """Steps the built-in UAV on sim time and answers the bridge's services."""

    def __init__(self, **options) -> None:
        super().__init__('builtin_uav', **options)
        try:
            params = declare_parameters(self, PARAMETERS)
            for name in ('inertia', 'attach_offset', 'start', 'pad'):
                if len(params[name]) != 3:
                    raise ValueError(f'parameter {name}: expected 3 numbers, got {params[name]}')
            if params['ground'] == 'pad' and params['reel_pose_rate'] < params['rate']:
                raise ValueError(f'parameter reel_pose_rate: {params["reel_pose_rate"]:g} Hz is below rate '
                                 f'{params["rate"]:g} Hz; every tick needs the pad\'s pose')
            if min(params['inertia']) <= 0.0:
                raise ValueError(f'parameter inertia: expected positive moments, got {params["inertia"]}')
            for name in ('state_rate', 'imu_rate'):
                if period_ns(1.0 / params[name]) % period_ns(1.0 / params['rate']):
                    raise ValueError(f'parameter {name}: {params[name]:g} Hz is not rate {params["rate"]:g} Hz '
                                     f'divided by a whole number (its messages go out at ticks)')
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.uav = BuiltinUav(BuiltinUavConfig(
            mass=params['mass'], inertia=tuple(np.diag(params['inertia'])), attach_offset=tuple(params['attach_offset']),
            start=tuple(params['start']), start_height=params['start_height'], land_speed=params['land_speed'],
            pad_radius=params['pad_radius']))
        self.uav.warm_up()
        self.pose_pub = self.create_publisher(PoseStamped, '/uav/pose', SENSOR)
        self.twist_pub = self.create_publisher(TwistStamped, '/uav/twist', SENSOR)
        self.imu_pub = self.create_publisher(Imu, '/uav/imu', SENSOR)
        self.state_pub = self.create_publisher(UavState, '/uav/state', STATE)
        # One message object per per-tick topic, every field refilled each tick (publish() serialises it at once)
        self.pose_msg, self.twist_msg, self.imu_msg = PoseStamped(), TwistStamped(), Imu()
        if not params['command_rate']:
            self.create_subscription(PoseStamped, '/uav/setpoint', self.setpoint_callback, COMMAND)
        self.create_service(SetMode, '/uav/set_mode', self.set_mode_callback)
        self.create_service(SetBool, '/uav/arm', self.arm_callback)
        self.create_service(Takeoff, '/uav/takeoff', self.takeoff_callback)
        self.create_service(Trigger, '/uav/land', self.land_callback)
        self.state_period_ns = period_ns(1.0 / params['state_rate'])
        self.imu_period_ns = period_ns(1.0 / params['imu_rate'])
        self.outcome = (0, False, '')
        self.lockstep = Lockstep(self)
        wrench_period = 1.0 / params['wrench_rate']
        inputs = ([Input('/tether/uav_wrench', WrenchStamped, wrench_period, wrench_period, STATE)]
                  if params['tether_force'] == 'topic' else [])
        if params['command_rate']:
            command_period = 1.0 / params['command_rate']
            inputs.append(Input('/uav/command', UavCommand, command_period, command_period, LOOP))
        self.pad = np.asarray(params['pad'], dtype=float) if params['ground'] == 'pad' else None
        if self.pad is not None:
            inputs.append(Input('/platform/reel_pose', PoseStamped, 1.0 / params['reel_pose_rate'], 0.0, STATE))
        self.lockstep.every(1.0 / params['rate'], self.step, inputs)
        commands = (f'/uav/command at {params["command_rate"]:g} Hz, one period late' if params['command_rate']
                    else 'services and /uav/setpoint on arrival')
        self.get_logger().info(f'built-in UAV: {params["mass"]:g} kg at {params["start"]} m in world'
                               + (f', hovering {params["start_height"]:g} m above' if params['start_height'] else '')
                               + f', {params["rate"]:g} Hz, tether force {params["tether_force"]}, commands by '
                               + commands)

    def step(self, tick: Tick) -> None:
        """Carry out the selected command, advance the body to the tick under the selected wrench, publish."""
        command = tick.inputs.get('/uav/command')
        if command is not None:
            self.carry_out(command)
        wrench = tick.inputs.get('/tether/uav_wrench')
        force = np.zeros(3) if wrench is None else np.array(
            [wrench.wrench.force.x, wrench.wrench.force.y, wrench.wrench.force.z])
        state = self.uav.step(tick.time_ns * 1e-9, force, self.pad_in_world(tick.inputs.get('/platform/reel_pose')))
        stamp = tick.stamp
        rotation = quaternion_rotation(state.quaternion, 'the UAV attitude')
        pose, twist, imu = self.pose_msg, self.twist_msg, self.imu_msg
        fill_pose_and_twist(pose, twist, stamp, state.position, state.quaternion, state.velocity,
                            rotation.apply(state.angular_velocity))
        self.pose_pub.publish(pose)
        self.twist_pub.publish(twist)
        if tick.time_ns % self.imu_period_ns == 0:
            imu.header.stamp, imu.header.frame_id = stamp, 'uav'
            fill_quaternion(imu.orientation, state.quaternion)
            fill_vector(imu.angular_velocity, state.angular_velocity)
            specific_force = state.acceleration + [0.0, 0.0, self.uav.config.gravity] if state.armed else \
                np.array([0.0, 0.0, self.uav.config.gravity])
            fill_vector(imu.linear_acceleration, rotation.apply_inverse(specific_force))
            self.imu_pub.publish(imu)
        if tick.time_ns % self.state_period_ns == 0:
            msg = UavState()
            msg.header.stamp = stamp
            msg.connected, msg.armed, msg.mode, msg.position_ready = True, state.armed, state.mode, True
            msg.ready = state.armed and state.mode == 'GUIDED'
            msg.heartbeat_age = 0.0
            msg.command_sequence, msg.command_success, msg.command_message = self.outcome
            self.state_pub.publish(msg)

    def pad_in_world(self, reel: PoseStamped | None):
        """Where the UAV rests on the pad (m, world) with the reel mount at ``reel`` (every tick has one:
        reel_pose_rate >= rate); None: level ground.
        """
        if self.pad is None:
            return None
        p, q = reel.pose.position, reel.pose.orientation
        rotation = quaternion_rotation(np.array([q.x, q.y, q.z, q.w]), '/platform/reel_pose').matrix
        return np.array([p.x, p.y, p.z]) + rotation @ self.pad

    def carry_out(self, command: UavCommand) -> None:
        """The command's request, once per sequence number, and its setpoint while it holds."""
        if command.sequence != self.outcome[0]:
            success, message = self.uav.request(command.request, command.mode, command.arm, command.altitude)
            self.outcome = (command.sequence, success, message)
        if command.hold:
            p = command.setpoint
            self.uav.setpoint([p.x, p.y, p.z])

    def setpoint_callback(self, msg: PoseStamped) -> None:
        """Position target in world."""
        if msg.header.frame_id in ('world', ''):
            p = msg.pose.position
            self.uav.setpoint([p.x, p.y, p.z])

    def set_mode_callback(self, request, response):
        """GUIDED or LAND."""
        response.success, response.message = self.uav.set_mode(request.mode)
        return response

    def arm_callback(self, request, response):
        """Arm or disarm."""
        response.success, response.message = self.uav.arm(request.data)
        return response

    def takeoff_callback(self, request, response):
        """Climb to the altitude above the take-off point."""
        response.success, response.message = self.uav.takeoff(request.altitude)
        return response

    def land_callback(self, request, response):
        """Land where the UAV is."""
        response.success, response.message = self.uav.land()
        return response


def main(args=None):
    """Run the built-in UAV."""
    sys.exit(run_node(BuiltinUavNode, args))


if __name__ == '__main__':
    main()
