"""ROS 2 node ``builtin_uav``: a UAV for runs without an autopilot, with the bridge's interface.

A thin wrapper around :class:`uav_bridge.builtin_uav.BuiltinUav` (the plant's UAV rigid body
under the cascaded station controller). It publishes what ``mavlink_bridge`` publishes —
``/uav/pose``, ``/uav/twist`` (``world``), ``/uav/imu`` (``uav``, FLU), ``/uav/state``
(transient local) — and serves the same ``/uav/set_mode``, ``/uav/arm``, ``/uav/takeoff``,
``/uav/land`` and ``/uav/setpoint``, so the mission node flies either one. The tether's force
on the UAV comes from the plant on ``/tether/uav_wrench`` (geometry_msgs/WrenchStamped,
world): the tick at t uses the latest wrench stamped at or before t minus one period (the
explicit delay of the UAV ↔ plant loop); none is zero force.
"""

from __future__ import annotations

import bisect
import sys

import numpy as np
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.time import Time
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import Imu
from std_srvs.srv import SetBool
from std_srvs.srv import Trigger
from tether_msgs.msg import UavState
from tether_msgs.srv import SetMode
from tether_msgs.srv import Takeoff

from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import COMMAND
from tether_common.qos import LATCHED
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from uav_bridge.builtin_uav import BuiltinUav
from uav_bridge.builtin_uav import BuiltinUavConfig
from uav_bridge.builtin_uav_params import PARAMETERS
from uav_bridge.ros_fill import fill_quaternion
from uav_bridge.ros_fill import fill_vector
from uav_bridge.ros_fill import pose_and_twist


class BuiltinUavNode(Node):
    """Steps the built-in UAV on sim time and answers the bridge's services."""

    def __init__(self) -> None:
        super().__init__('builtin_uav')
        try:
            params = declare_parameters(self, PARAMETERS)
            for name in ('inertia', 'attach_offset', 'start'):
                if len(params[name]) != 3:
                    raise ValueError(f'parameter {name}: expected 3 numbers, got {params[name]}')
            if min(params['inertia']) <= 0.0:
                raise ValueError(f'parameter inertia: expected positive moments, got {params["inertia"]}')
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.uav = BuiltinUav(BuiltinUavConfig(
            mass=params['mass'], inertia=tuple(np.diag(params['inertia'])), attach_offset=tuple(params['attach_offset']),
            start=tuple(params['start']), land_speed=params['land_speed']))
        self.period_ns = round(1e9 / params['rate'])
        self.wrench_stamps: list[int] = []
        self.wrench_forces: list[np.ndarray] = []
        self.pose_pub = self.create_publisher(PoseStamped, '/uav/pose', SENSOR)
        self.twist_pub = self.create_publisher(TwistStamped, '/uav/twist', SENSOR)
        self.imu_pub = self.create_publisher(Imu, '/uav/imu', SENSOR)
        self.state_pub = self.create_publisher(UavState, '/uav/state', LATCHED)
        self.create_subscription(WrenchStamped, '/tether/uav_wrench', self.wrench_callback, STATE)
        self.create_subscription(PoseStamped, '/uav/setpoint', self.setpoint_callback, COMMAND)
        self.create_service(SetMode, '/uav/set_mode', self.set_mode_callback)
        self.create_service(SetBool, '/uav/arm', self.arm_callback)
        self.create_service(Takeoff, '/uav/takeoff', self.takeoff_callback)
        self.create_service(Trigger, '/uav/land', self.land_callback)
        self._last_state: tuple | None = None
        self._next_state_ns = 0
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / params['rate'], self.step)
        self.get_logger().info(f'built-in UAV: {params["mass"]:g} kg at {params["start"]} m in world, '
                               f'{params["rate"]:g} Hz')

    def wrench_callback(self, msg: WrenchStamped) -> None:
        """Keep the plant's wrenches by stamp."""
        stamp = Time.from_msg(msg.header.stamp).nanoseconds
        f = msg.wrench.force
        index = bisect.bisect(self.wrench_stamps, stamp)
        self.wrench_stamps.insert(index, stamp)
        self.wrench_forces.insert(index, np.array([f.x, f.y, f.z]))

    def _force_for(self, tick_ns: int) -> np.ndarray:
        index = bisect.bisect(self.wrench_stamps, tick_ns - self.period_ns)
        if index == 0:
            return np.zeros(3)
        force = self.wrench_forces[index - 1]
        del self.wrench_stamps[:index - 1], self.wrench_forces[:index - 1]
        return force

    def step(self, tick: Tick) -> None:
        """Advance the body to the tick and publish it."""
        state = self.uav.step(tick.time_ns * 1e-9, self._force_for(tick.time_ns))
        stamp = tick.stamp
        rotation = Rotation.from_quat(state.quaternion)
        pose, twist = pose_and_twist(stamp, state.position, state.quaternion, state.velocity,
                                     rotation.apply(state.angular_velocity))
        self.pose_pub.publish(pose)
        self.twist_pub.publish(twist)
        imu = Imu()
        imu.header.stamp, imu.header.frame_id = stamp, 'uav'
        fill_quaternion(imu.orientation, state.quaternion)
        fill_vector(imu.angular_velocity, state.angular_velocity)
        specific_force = state.acceleration + [0.0, 0.0, self.uav.config.gravity] if state.armed else \
            np.array([0.0, 0.0, self.uav.config.gravity])
        fill_vector(imu.linear_acceleration, rotation.inv().apply(specific_force))
        self.imu_pub.publish(imu)
        key = (state.armed, state.mode)
        if key != self._last_state or tick.time_ns >= self._next_state_ns:
            self._last_state = key
            self._next_state_ns = tick.time_ns + 1_000_000_000
            msg = UavState()
            msg.header.stamp = stamp
            msg.connected, msg.armed, msg.mode, msg.position_ready = True, state.armed, state.mode, True
            msg.ready = state.armed and state.mode == 'GUIDED'
            msg.heartbeat_age = 0.0
            self.state_pub.publish(msg)

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
