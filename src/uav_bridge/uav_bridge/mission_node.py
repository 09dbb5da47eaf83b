"""ROS 2 node ``mission``: take off, hold station over the boat, land (thesis Sec. 5.3, 5.4).

A thin wrapper around :class:`uav_bridge.mission.MissionLogic`, stepped by a sim-time timer
(lockstep ticks, :mod:`tether_common.lockstep`) at ``rate``. It reads ``/uav/state`` and
``/uav/pose`` (from the MAVLink bridge or the built-in UAV) and ``/reel/state``; it asks the
UAV through the services ``/uav/set_mode``, ``/uav/arm``, ``/uav/takeoff``, ``/uav/land``
(one request at a time, the answer fed to the next step), publishes the station on
``/uav/setpoint`` (geometry_msgs/PoseStamped, ``world``, zero quaternion: heading kept) while
holding, and its phase on ``/mission/state`` (tether_msgs/MissionState, transient local).

A reel trip lands the UAV: the reel in its fault mode (ReelState.MODE_FAULT: a safety trip
holds it, its reason in ``/reel/diagnostics`` ``safety_trip``) for ``abort_after`` s, or a
tension estimate above ``abort_tension`` (:class:`uav_bridge.mission.TripMonitor`).
"""

from __future__ import annotations

import math
import sys

import numpy as np
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from std_srvs.srv import SetBool
from std_srvs.srv import Trigger
from tether_msgs.msg import MissionState
from tether_msgs.msg import ReelControllerDiagnostics
from tether_msgs.msg import ReelState
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
from uav_bridge.mission import Inputs
from uav_bridge.mission import MissionConfig
from uav_bridge.mission import MissionLogic
from uav_bridge.mission import TripMonitor
from uav_bridge.mission_params import PARAMETERS


class MissionNode(Node):
    """Steps the mission logic and carries out its requests."""

    def __init__(self) -> None:
        super().__init__('mission')
        try:
            params = declare_parameters(self, PARAMETERS)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.logic = MissionLogic(MissionConfig(
            altitude=params['altitude'], radial=params['radial'], bearing=math.radians(params['bearing']),
            land_time=params['land_time'] or math.inf, climb_tolerance=params['climb_tolerance'],
            retry_period=params['retry_period']))
        self.abort_tension = params['abort_tension']
        self.trips = TripMonitor(params['abort_after'])
        self.trip_reason = ''
        self.uav_state: UavState | None = None
        self.position: np.ndarray | None = None
        self.reel_fault = ''
        self.pending = None
        self.answer = None
        self.create_subscription(UavState, '/uav/state', self.uav_state_callback, LATCHED)
        self.create_subscription(PoseStamped, '/uav/pose', self.pose_callback, SENSOR)
        self.create_subscription(ReelState, '/reel/state', self.reel_callback, STATE)
        self.create_subscription(ReelControllerDiagnostics, '/reel/diagnostics', self.diagnostics_callback, STATE)
        self.setpoint_pub = self.create_publisher(PoseStamped, '/uav/setpoint', COMMAND)
        self.state_pub = self.create_publisher(MissionState, '/mission/state', LATCHED)
        self.uav_services = {'set_mode': (self.create_client(SetMode, '/uav/set_mode'), lambda v: SetMode.Request(mode=v)),
                        'arm': (self.create_client(SetBool, '/uav/arm'), lambda v: SetBool.Request(data=v)),
                        'takeoff': (self.create_client(Takeoff, '/uav/takeoff'),
                                    lambda v: Takeoff.Request(altitude=float(v))),
                        'land': (self.create_client(Trigger, '/uav/land'), lambda v: Trigger.Request())}
        self._published = None
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / params['rate'], self.step)
        station = self.logic.station
        self.get_logger().info(f'mission: station {station[2]:g} m up, {math.hypot(*station[:2]):g} m radial '
                               f'(Δr/Δz {math.hypot(*station[:2]) / station[2]:.2f}) in world')

    def uav_state_callback(self, msg: UavState) -> None:
        """Keep the latest UAV state."""
        self.uav_state = msg

    def pose_callback(self, msg: PoseStamped) -> None:
        """Keep the latest UAV position in world."""
        p = msg.pose.position
        self.position = np.array([p.x, p.y, p.z])

    def diagnostics_callback(self, msg: ReelControllerDiagnostics) -> None:
        """Keep the reason of the reel's active safety trip."""
        self.trip_reason = msg.safety_trip

    def reel_callback(self, msg: ReelState) -> None:
        """Feed the trip monitor: fault mode, or tension above the abort threshold."""
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        if msg.mode == ReelState.MODE_FAULT:
            reason = f'reel in fault mode ({self.trip_reason})' if self.trip_reason else 'reel in fault mode'
            self.reel_fault = self.trips.update(t, True, reason)
        elif self.abort_tension > 0.0 and msg.tension_estimate > self.abort_tension:
            self.reel_fault = self.trips.update(
                t, True, f'tension estimate {msg.tension_estimate:.1f} N > {self.abort_tension:g} N')
        else:
            self.reel_fault = self.trips.update(t, False, '')

    def step(self, tick: Tick) -> None:
        """One mission step at the tick's sim time."""
        state = self.uav_state
        inputs = Inputs(
            connected=bool(state and state.connected and not state.stale),
            position_ready=bool(state and state.position_ready), armed=bool(state and state.armed),
            mode=state.mode if state else '', position=self.position, reel_fault=self.reel_fault,
            busy=self.pending is not None, answer=self.answer)
        self.answer = None
        out = self.logic.step(tick.time_ns * 1e-9, inputs)
        if out.request is not None:
            self._request(*out.request)
        if out.setpoint is not None:
            msg = PoseStamped()
            msg.header.stamp, msg.header.frame_id = tick.stamp, 'world'
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in out.setpoint)
            msg.pose.orientation.w = 0.0
            self.setpoint_pub.publish(msg)
        if (out.phase, out.reason) != self._published:
            self._published = (out.phase, out.reason)
            self.get_logger().info(f'mission phase {out.phase}' + (f': {out.reason}' if out.reason else ''))
            msg = MissionState()
            msg.header.stamp = tick.stamp
            msg.phase, msg.reason, msg.aborted = out.phase, out.reason, self.logic.aborted
            msg.station.x, msg.station.y, msg.station.z = (float(v) for v in self.logic.station)
            self.state_pub.publish(msg)

    def _request(self, kind: str, value) -> None:
        client, build = self.uav_services[kind]
        if not client.service_is_ready():
            self.answer = (kind, False, f'service of {kind} not available')
            return
        self.pending = kind
        future = client.call_async(build(value))
        future.add_done_callback(lambda done: self._answered(kind, done))

    def _answered(self, kind: str, future) -> None:
        self.pending = None
        error = future.exception()
        self.answer = (kind, False, str(error)) if error else (kind, future.result().success, future.result().message)


def main(args=None):
    """Run the mission node."""
    sys.exit(run_node(MissionNode, args))


if __name__ == '__main__':
    main()
