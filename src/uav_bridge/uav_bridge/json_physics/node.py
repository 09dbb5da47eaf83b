"""ROS 2 node ``json_physics``: the UAV that ArduPilot SITL (``--model JSON``) flies, in the graph's lockstep.

A thin wrapper around :class:`uav_bridge.json_physics.server.JsonPhysicsServer`. SITL sends a
servo packet per physics frame and waits for the reply; this node answers them only inside
its lockstep ticks (:mod:`tether_common.lockstep`): the tick at sim time t answers SITL's
frames until the physics time reaches t, waits for SITL's next servo packet (SITL then waits
for the reply, its loop at t done), then publishes the UAV at t and acks. So SITL runs
only as fast as the graph's clock advances, the clock advances only once the physics reached
it, and SITL's clock (the physics timestamps) is the graph's sim time: one time axis, the
same flight at any ``--speedup`` (SITL's speed-up only caps its pace). A MAVLink bridge that
takes ``/uav/pose`` as its lockstep input (delay 0) writes to SITL only while SITL waits, and
the frames after t are answered only once every node acked t (the scene's ``lockstep_window``
0): its bytes reach SITL at the same frame at any pace.

The tether's force on the UAV comes from the plant on ``/tether/uav_wrench``
(geometry_msgs/WrenchStamped, world): the tick at t holds the wrench stamped t - 1/wrench_rate
over its frames (the explicit delay of the UAV <-> plant loop); none is zero force. With
``tether_model: straight_line`` it comes instead from ArduPilot's SIM_Tether model
(:class:`uav_bridge.json_physics.server.StraightTether`, the bench's too): a straight line from
the reel mount (``/platform/reel_pose`` of the tick) with the plant's deployed length
(``/tether/state`` one plant step old), for the comparison of the two on the same mission.
The force applied is published on ``/uav/tether_force`` (geometry_msgs/WrenchStamped, world),
the rotors' total thrust on ``/uav/rotor_thrust`` (geometry_msgs/WrenchStamped, ``uav``, FLU:
along +z), both at the tick's last frame.
Publishes, like the built-in UAV and the bridge: ``/uav/pose``, ``/uav/twist`` (``world``) and
``/uav/imu`` (``uav``, FLU: the specific force SITL's IMU reads). ArduPilot's state, the
commands and the setpoints go over MAVLink (``mavlink_bridge``, ``mission``).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from geometry_msgs.msg import WrenchStamped
from tether_msgs.msg import TetherState
from rclpy.node import Node
from sensor_msgs.msg import Imu

from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.rotation import quaternion_rotation
from tether_models.constants import GRAVITY
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import JsonPhysicsConfig
from uav_bridge.json_physics.params import PARAMETERS
from uav_bridge.json_physics.protocol import physics_port
from uav_bridge.json_physics.quad_motors import QuadXConfig
from uav_bridge.json_physics.server import HeldForce
from uav_bridge.json_physics.server import JsonPhysicsServer
from uav_bridge.json_physics.server import PlatformPose
from uav_bridge.json_physics.server import StraightTether
from uav_bridge.ros_fill import pose_and_twist

WAIT_LOG_PERIOD = 10.0      # s of wall time between "waiting for SITL" lines


class JsonPhysicsNode(Node):
    """Answers SITL's frames tick by tick and publishes the UAV."""

    def __init__(self) -> None:
        super().__init__('json_physics')
        try:
            p = declare_parameters(self, PARAMETERS)
            for name in ('inertia', 'attach_offset', 'start'):
                if len(p[name]) != 3:
                    raise ValueError(f'parameter {name}: expected 3 numbers, got {p[name]}')
            if min(p['inertia']) <= 0.0:
                raise ValueError(f'parameter inertia: expected positive moments, got {p["inertia"]}')
            self.tick_ns = round(1e9 / p['rate'])
            frame_ns = round(1e9 / p['frame_rate'])
            if self.tick_ns % frame_ns:
                raise ValueError(f'parameter frame_rate: a frame of {frame_ns} ns does not divide the tick of '
                                 f'{self.tick_ns} ns (rate {p["rate"]:g} Hz)')
            vehicle = QuadXConfig(mass=p['mass'], inertia=tuple(np.diag(p['inertia'])), arm=p['arm'],
                                  max_thrust=p['max_thrust'], thrust_expo=p['thrust_expo'],
                                  torque_ratio=p['torque_ratio'], time_constant=p['time_constant'])
            self.physics = JsonPhysics(JsonPhysicsConfig(
                vehicle=vehicle, attach_offset=tuple(p['attach_offset']), start=tuple(p['start']),
                heading=np.radians(p['heading']), frame_rate=p['frame_rate']))
            self.straight_line = p['tether_model'] == 'straight_line'
            if self.straight_line and p['wrench_rate'] <= 0.0:
                raise ValueError('parameter tether_model: straight_line needs the plant (wrench_rate > 0) for its '
                                 'deployed length')
            self.anchor = PlatformPose(np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]), np.zeros(3), np.zeros(3))
            self.force = StraightTether(
                lambda t: self.anchor, (0.0, 0.0, 0.0), p['line_density'], math.inf, GRAVITY,
                1.0 / p['frame_rate'], p['line_spring'], p['line_damping']) if self.straight_line else HeldForce()
            port = physics_port(p['instance'])
            self.server = JsonPhysicsServer(self.physics, port, tether=self.force, log=self.get_logger().info)
            self.server.warm_up()       # compiled before the lockstep, not inside a reply to SITL
        except OSError as error:
            raise ConfigurationError(f'UDP port {physics_port(p["instance"])}: {error.strerror}') from None
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.pose_pub = self.create_publisher(PoseStamped, '/uav/pose', SENSOR)
        self.twist_pub = self.create_publisher(TwistStamped, '/uav/twist', SENSOR)
        self.imu_pub = self.create_publisher(Imu, '/uav/imu', SENSOR)
        self.force_pub = self.create_publisher(WrenchStamped, '/uav/tether_force', STATE)
        self.thrust_pub = self.create_publisher(WrenchStamped, '/uav/rotor_thrust', STATE)
        inputs = []
        if p['wrench_rate'] > 0.0:
            period = 1.0 / p['wrench_rate']
            inputs.append(Input('/tether/uav_wrench', WrenchStamped, period, period, STATE))
            if self.straight_line:
                inputs += [Input('/tether/state', TetherState, period, period, STATE),
                           Input('/platform/reel_pose', PoseStamped, 1.0 / p['platform_rate'], 0.0, STATE)]
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / p['rate'], self.step, inputs)
        self.get_logger().info(f'JSON physics for SITL instance {p["instance"]} on UDP {port}: {p["mass"]:g} kg '
                               f'quad X at {p["start"]} m, {p["frame_rate"]} frames/s')

    def step(self, tick: Tick) -> None:
        """Answer SITL's frames up to the tick's time, then publish the UAV."""
        wrench = tick.inputs.get('/tether/uav_wrench')
        if self.straight_line:
            state, reel = tick.inputs['/tether/state'], tick.inputs['/platform/reel_pose']
            if state is not None:
                self.force.max_length = state.deployed_length
            if reel is not None:
                r = reel.pose.position
                self.anchor = PlatformPose(np.array([r.x, r.y, r.z]), self.anchor.quaternion, np.zeros(3), np.zeros(3))
        elif wrench is not None:
            f = wrench.wrench.force
            self.force.value = np.array([f.x, f.y, f.z])
        waiting_since = time.monotonic()
        logged = waiting_since
        while self.physics.time_ns < tick.time_ns or not self.server.waiting(0.0):
            if not rclpy.ok():
                return
            if self.physics.time_ns < tick.time_ns and self.server.poll(0.5):
                waiting_since = time.monotonic()
            elif self.physics.time_ns >= tick.time_ns and self.server.waiting(0.5):
                break
            elif time.monotonic() - logged > WAIT_LOG_PERIOD:
                logged = time.monotonic()
                self.get_logger().info(f'tick {tick.seconds:.3f} s waits for SITL\'s servo packets on UDP '
                                       f'{self.server.port} (none for {logged - waiting_since:.0f} s)')
        self.publish(tick)

    def publish(self, tick: Tick) -> None:
        """The UAV at the tick: pose, twist, IMU."""
        frame = self.physics.frame
        rotation = quaternion_rotation(frame.quaternion, 'the UAV attitude')
        pose, twist = pose_and_twist(tick.stamp, frame.position, frame.quaternion, frame.velocity,
                                     rotation.apply(frame.angular_velocity))
        self.pose_pub.publish(pose)
        self.twist_pub.publish(twist)
        imu = Imu()
        imu.header.stamp, imu.header.frame_id = tick.stamp, 'uav'
        fill_quaternion(imu.orientation, frame.quaternion)
        fill_vector(imu.angular_velocity, frame.angular_velocity)
        fill_vector(imu.linear_acceleration, frame.specific_force)
        self.imu_pub.publish(imu)
        force = WrenchStamped()
        force.header.stamp, force.header.frame_id = tick.stamp, 'world'
        fill_vector(force.wrench.force, self.force.force())
        self.force_pub.publish(force)
        thrust = WrenchStamped()
        thrust.header.stamp, thrust.header.frame_id = tick.stamp, 'uav'
        thrust.wrench.force.z = float(frame.thrusts.sum())
        self.thrust_pub.publish(thrust)

    def destroy_node(self) -> None:
        """Say what the frames were and release the UDP port with the node."""
        c = self.physics.counts
        self.get_logger().info(f'frames: {c.stepped} stepped to {self.physics.t:.3f} s, {c.resent} answered again, '
                               f'{c.lost} lost, {c.restarts} SITL restarts, {c.rejected} datagrams rejected')
        self.server.close()
        super().destroy_node()


def main(args=None):
    """Run the JSON physics node."""
    sys.exit(run_node(JsonPhysicsNode, args))


if __name__ == '__main__':
    main()
