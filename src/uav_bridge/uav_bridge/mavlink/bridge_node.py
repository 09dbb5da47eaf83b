"""ROS 2 node ``mavlink_bridge``: an ArduPilot autopilot over MAVLink, in ROS conventions.

A thin wrapper around :class:`uav_bridge.mavlink.session.MavlinkSession`, whose thread owns the
link, so the executor never waits on I/O. Publishes, stamped with the graph's clock at
arrival:

* ``/uav/pose`` (geometry_msgs/PoseStamped, frame ``world``, ENU; orientation of the FLU
  body ``uav``) and ``/uav/twist`` (geometry_msgs/TwistStamped, frame ``world``: ENU
  velocity and angular velocity expressed in world), from LOCAL_POSITION_NED + ATTITUDE;
* ``/uav/imu`` (sensor_msgs/Imu, frame ``uav``, FLU), from HIGHRES_IMU;
* ``/uav/global`` (sensor_msgs/NavSatFix, frame ``uav``; altitude above mean sea level), from
  GLOBAL_POSITION_INT;
* ``/uav/state`` (tether_msgs/UavState, reliable, transient local), on every change and at
  least every ``status_period``: link, staleness, armed, mode, position estimate, what the
  link waits for, latest STATUSTEXT lines, offset of the graph clock to the autopilot's
  time since boot.

The pose, twist, imu and global topics live under ``telemetry_namespace`` (default ``/uav``;
``/autopilot`` in scenes where the JSON physics node publishes the true ``/uav/pose``).
Streams use the sensor-data QoS. Commands: services ``/uav/set_mode`` (tether_msgs/SetMode),
``/uav/arm`` (std_srvs/SetBool: true arms, retrying with back-off while the autopilot
refuses, false disarms), ``/uav/takeoff`` (tether_msgs/Takeoff), ``/uav/land``
(std_srvs/Trigger); position setpoints on ``/uav/setpoint`` (geometry_msgs/PoseStamped in
``world``; a zero quaternion keeps the heading) go out as SET_POSITION_TARGET_LOCAL_NED
(stepped: in the tick after their stamp).
Services answer once the autopilot did (or refused, with its reasons), in their own threads.

With ``lockstep_input`` (SITL on the JSON physics, :mod:`uav_bridge.json_physics.node`) the
bridge ticks in the graph's lockstep after the physics' message of the same tick, when SITL
waits for its next frame: each tick reads what SITL sent, runs the link's timers on sim time,
sends the queued commands and setpoints, publishes (stamped with the tick) and only then acks,
so SITL reads every byte at the same frame at any pace (:meth:`MavlinkSession.poll`).
With ``command_rate`` as well, the mission commands the autopilot as it commands the built-in
UAV (``uav_link: command``): ``/uav/command`` (tether_msgs/UavCommand) is a lockstep input one
command period P late; the tick at t takes the command stamped t − P, starts its request once
per sequence number (the session's mode, arm, takeoff or land) and sends its setpoint once
per command while it holds, before the tick's poll. ``/uav/state`` then goes out at every
multiple of 1/``state_rate`` only, stamped with the tick, with the outcome of the latest
request that has ended (``command_sequence``, ``command_success``, ``command_message``): a
run's commands, their answers and ArduPilot's flight are fixed by stamps, as with the
built-in UAV. The services then refuse at once, naming ``/uav/command``, and ``/uav/setpoint``
is not subscribed, so no callback waits for a tick and the node spins on the single-threaded
events executor instead of the multi-threaded one.
"""

from __future__ import annotations

import itertools
import sys
import threading
from collections.abc import Callable
from concurrent.futures import Future

from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.time import Time
from sensor_msgs.msg import Imu
from sensor_msgs.msg import NavSatFix
from sensor_msgs.msg import NavSatStatus
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
from tether_common.lockstep import stamp_ns
from tether_common.node_main import ConfigurationError
from tether_common.node_main import make_executor
from tether_common.node_main import run_node
from tether_common.qos import COMMAND
from tether_common.qos import LOOP
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from uav_bridge.frames import quaternion_enu_to_yaw_ned
from uav_bridge.mavlink import telemetry
from uav_bridge.mavlink.bridge_params import PARAMETERS
from uav_bridge.mavlink.session import CommandResult
from uav_bridge.mavlink.session import LinkStatus
from uav_bridge.mavlink.session import MavlinkSession
from uav_bridge.mavlink.session import SessionConfig
from uav_bridge.ros_fill import pose_and_twist

WORLD_FRAMES = ('world', '')


class MavlinkBridge(Node):
    """Publishes an autopilot's telemetry and state; forwards commands and setpoints."""

    def __init__(self) -> None:
        super().__init__('mavlink_bridge')
        try:
            params = declare_parameters(self, PARAMETERS)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        if len(params['origin']) != 3:
            raise ConfigurationError(f'parameter origin: expected 3 numbers (m, ENU), got {params["origin"]}')
        config = SessionConfig(
            url=params['url'], origin=tuple(params['origin']), system_id=params['system_id'],
            component_id=params['component_id'], heartbeat_period=params['heartbeat_period'],
            link_timeout=params['link_timeout'], reconnect_max=params['reconnect_max'],
            stream_rates={'ATTITUDE': params['pose_rate'], 'LOCAL_POSITION_NED': params['pose_rate'],
                          'HIGHRES_IMU': params['imu_rate'], 'GLOBAL_POSITION_INT': params['global_rate'],
                          'EKF_STATUS_REPORT': params['ekf_status_rate']},
            stream_timeout=params['stream_timeout'], status_period=params['status_period'],
            command_timeout=params['command_timeout'], arm_timeout=params['arm_timeout'],
            statustext_lines=params['statustext_lines'])
        telemetry = params['telemetry_namespace'].rstrip('/')
        if not telemetry.startswith('/'):
            raise ConfigurationError(f'parameter telemetry_namespace: expected an absolute namespace, got {telemetry!r}')
        self.pose_pub = self.create_publisher(PoseStamped, f'{telemetry}/pose', SENSOR)
        self.twist_pub = self.create_publisher(TwistStamped, f'{telemetry}/twist', SENSOR)
        self.imu_pub = self.create_publisher(Imu, f'{telemetry}/imu', SENSOR)
        self.global_pub = self.create_publisher(NavSatFix, f'{telemetry}/global', SENSOR)
        self.state_pub = self.create_publisher(UavState, '/uav/state', STATE)
        stepped = bool(params['lockstep_input'])
        if params['command_rate'] and not stepped:
            raise ConfigurationError('parameter command_rate: /uav/command is a lockstep input, taken only with '
                                     'lockstep_input (SITL on the JSON physics); 0 for services')
        self._tick_seconds = 0.0
        clocks = {'clock': self._tick_time, 'stamp_clock': self._tick_time} if stepped else \
            {'stamp_clock': self._graph_seconds}
        self.commanded = bool(params['command_rate'])
        try:
            self.session = MavlinkSession(config, self.on_sample, None if self.commanded else self.on_status,
                                          self.on_log, **clocks)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        # stepped, the session ends every command by its deadline in sim time, however slow the graph
        self.command_timeout = None if stepped else max(config.command_timeout, config.arm_timeout) + 5.0
        group = ReentrantCallbackGroup()
        self.create_service(SetMode, '/uav/set_mode', self.set_mode_callback, callback_group=group)
        self.create_service(SetBool, '/uav/arm', self.arm_callback, callback_group=group)
        self.create_service(Takeoff, '/uav/takeoff', self.takeoff_callback, callback_group=group)
        self.create_service(Trigger, '/uav/land', self.land_callback, callback_group=group)
        if not self.commanded:
            self.create_subscription(PoseStamped, '/uav/setpoint', self.setpoint_callback, COMMAND)
        self._warned_frames: set[str] = set()
        self.lockstep: Lockstep | None = None
        self._due: list[tuple[int, int, Callable[[], Future | None], Future]] = []
        self._due_lock = threading.Lock()
        self._arrivals = itertools.count()
        if stepped:
            self.lockstep = Lockstep(self)
            period = 1.0 / params['lockstep_rate']
            self._period_ns = period_ns(period)
            inputs = [Input(params['lockstep_input'], PoseStamped, period, 0.0)]
            if params['command_rate']:
                command_period = 1.0 / params['command_rate']
                inputs.append(Input('/uav/command', UavCommand, command_period, command_period, LOOP))
            self.lockstep.every(period, self.step, inputs)
        self.state_period_ns = period_ns(1.0 / params['state_rate'])
        self.outcome = (0, False, '')
        self._taken_sequence = 0
        self._command_stamp = -1
        self.session.start(stepped=stepped)
        self.get_logger().info(f'MAVLink bridge on {config.url}; autopilot origin at {list(config.origin)} m in world')

    def destroy_node(self) -> None:
        """Stop the link thread before the node goes; a request still waiting for its tick is refused."""
        self.session.stop()
        with self._due_lock:
            due, self._due = self._due, []
        for _, _, _, outer in due:
            outer.set_result(CommandResult(False, 'the bridge stopped'))
        super().destroy_node()

    def _graph_seconds(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _tick_time(self) -> float:
        return self._tick_seconds

    def step(self, tick: Tick) -> None:
        """Lockstep tick: the link's work at the tick's sim time (SITL waits for its next frame meanwhile).

        The commands and setpoints due by the tick go to the session first (in due, then arrival,
        order), so they are sent in this tick's :meth:`MavlinkSession.poll`.
        """
        self._tick_seconds = tick.seconds
        command = tick.inputs.get('/uav/command')
        if command is not None and stamp_ns(command.header.stamp) != self._command_stamp:
            self._command_stamp = stamp_ns(command.header.stamp)
            self.carry_out(command)
        with self._due_lock:
            due = sorted(item for item in self._due if item[0] <= tick.time_ns)
            self._due = [item for item in self._due if item[0] > tick.time_ns]
        for _, _, action, outer in due:
            inner = action()
            if inner is None:
                outer.set_result(None)
            else:
                inner.add_done_callback(lambda done, outer=outer: outer.set_result(done.result()))
        self.session.poll(tick.seconds)
        if self.commanded and tick.time_ns % self.state_period_ns == 0:
            self._publish_status(self.session.status(tick.seconds))

    def carry_out(self, command: UavCommand) -> None:
        """The command's request, once per sequence number (its outcome kept once the session ends it), and its
        setpoint while it holds (a zero quaternion: the heading kept).
        """
        if command.sequence != self._taken_sequence:
            self._taken_sequence = sequence = command.sequence
            requests = {'set_mode': lambda: self.session.set_mode(command.mode),
                        'arm': lambda: self.session.arm(command.arm),
                        'takeoff': lambda: self.session.takeoff(command.altitude),
                        'land': self.session.land}
            if command.request not in requests:
                self.outcome = (sequence, False, f'unknown request {command.request!r}; known: {", ".join(requests)}')
            else:
                requests[command.request]().add_done_callback(
                    lambda done: self._answered(sequence, done.result()))
        if command.hold:
            p = command.setpoint
            self.session.send_setpoint([p.x, p.y, p.z], None)

    def _answered(self, sequence: int, result: CommandResult) -> None:
        self.outcome = (sequence, result.success, result.message)

    def _at_tick(self, due_ns: int, action: Callable[[], Future | None]) -> Future:
        """Run ``action`` in the first tick at or after ``due_ns``; its future's result, forwarded."""
        outer: Future = Future()
        with self._due_lock:
            self._due.append((due_ns, next(self._arrivals), action, outer))
        return outer

    def _command(self, action: Callable[[], Future]) -> Future:
        """A session command: at once, or stepped in the tick after the one the request arrived in
        (the mission's request of tick t goes out at t + one tick, as its setpoints do); refused at
        once while the mission commands on /uav/command.
        """
        if self.commanded:
            refused: Future = Future()
            refused.set_result(CommandResult(False, 'the mission commands this UAV on /uav/command '
                                                    '(command_rate); the services are off'))
            return refused
        if self.lockstep is None:
            return action()
        return self._at_tick(self.lockstep.clock_ns + self._period_ns, action)

    # link thread → ROS

    def on_log(self, level: str, text: str) -> None:
        """Forward the session's log lines to the node's logger (nothing once shutting down)."""
        if not self.context.ok():
            return
        logger = self.get_logger()
        if level == 'error':
            logger.error(text)
        elif level == 'warn':
            logger.warning(text)
        else:
            logger.info(text)

    def on_sample(self, sample, stamp: float) -> None:
        """Publish a sample; a shutdown racing the link thread drops it."""
        try:
            self._publish_sample(sample, stamp)
        except Exception:
            if self.context.ok():
                raise

    def on_status(self, status: LinkStatus) -> None:
        """Publish /uav/state on a change (commanded, the session pushes none: :meth:`step` publishes it at its
        ticks); a shutdown racing the link thread drops it.
        """
        try:
            self._publish_status(status)
        except Exception:
            if self.context.ok():
                raise

    def _publish_sample(self, sample, stamp: float) -> None:
        header_stamp = Time(nanoseconds=round(stamp * 1e9)).to_msg()
        if isinstance(sample, telemetry.Kinematics):
            pose, twist = pose_and_twist(header_stamp, sample.position, sample.orientation, sample.velocity,
                                         sample.angular_velocity)
            self.pose_pub.publish(pose)
            self.twist_pub.publish(twist)
        elif isinstance(sample, telemetry.ImuSample):
            imu = Imu()
            imu.header.stamp, imu.header.frame_id = header_stamp, 'uav'
            fill_quaternion(imu.orientation, sample.orientation)
            fill_vector(imu.angular_velocity, sample.angular_velocity)
            fill_vector(imu.linear_acceleration, sample.linear_acceleration)
            self.imu_pub.publish(imu)
        elif isinstance(sample, telemetry.GlobalFix):
            fix = NavSatFix()
            fix.header.stamp, fix.header.frame_id = header_stamp, 'uav'
            fix.status.status = NavSatStatus.STATUS_FIX if sample.valid else NavSatStatus.STATUS_NO_FIX
            fix.status.service = NavSatStatus.SERVICE_GPS
            fix.latitude, fix.longitude, fix.altitude = sample.latitude, sample.longitude, sample.altitude
            fix.position_covariance_type = NavSatFix.COVARIANCE_TYPE_UNKNOWN
            self.global_pub.publish(fix)

    def _publish_status(self, status: LinkStatus) -> None:
        msg = UavState()
        msg.header.stamp = Time(nanoseconds=round(status.stamp * 1e9)).to_msg()
        msg.connected, msg.armed, msg.ready, msg.mode = status.connected, status.armed, status.ready, status.mode
        msg.stale, msg.position_ready, msg.ekf_flags = status.stale, status.position_ready, status.ekf_flags
        msg.waiting_for, msg.heartbeat_age = status.waiting_for, float(status.heartbeat_age)
        msg.autopilot_time_offset = float(status.time_offset)
        msg.reconnects, msg.reboots, msg.bad_packets = status.reconnects, status.reboots, status.bad_packets
        msg.status_text = list(status.status_text)
        msg.command_sequence, msg.command_success, msg.command_message = self.outcome
        self.state_pub.publish(msg)

    # ROS → link thread

    def setpoint_callback(self, msg: PoseStamped) -> None:
        """Send a world-frame position (and heading, unless the quaternion is zero) target."""
        frame = msg.header.frame_id
        if frame not in WORLD_FRAMES:
            if frame not in self._warned_frames:
                self._warned_frames.add(frame)
                self.get_logger().warning(f'/uav/setpoint in frame {frame!r} ignored: setpoints are in world (ENU)')
            return
        q = msg.pose.orientation
        quaternion = [q.x, q.y, q.z, q.w]
        yaw = quaternion_enu_to_yaw_ned(quaternion) if any(quaternion) else None
        p = msg.pose.position
        position = [p.x, p.y, p.z]
        if self.lockstep is None:
            self.session.send_setpoint(position, yaw)
        else:
            self._at_tick(stamp_ns(msg.header.stamp) + self._period_ns,
                          lambda: self.session.send_setpoint(position, yaw))

    def set_mode_callback(self, request, response):
        """Ask for a flight mode; answer when the HEARTBEAT shows it or the autopilot refused."""
        return self._answer(self._command(lambda: self.session.set_mode(request.mode)), response)

    def arm_callback(self, request, response):
        """Arm (retrying while refused) or disarm."""
        return self._answer(self._command(lambda: self.session.arm(request.data)), response)

    def takeoff_callback(self, request, response):
        """Take off to the requested altitude above the take-off point."""
        return self._answer(self._command(lambda: self.session.takeoff(request.altitude)), response)

    def land_callback(self, request, response):
        """Land where the UAV is."""
        return self._answer(self._command(self.session.land), response)

    def _answer(self, future, response):
        """Wait for the session's answer: the session ends every command by its own time-out, so this wait's
        (their longest plus 5 s, wall clock; stepped, the node's end resolves what the ticks did not) is a
        safety net, answered as a refusal with its reason in one line when it fires.
        """
        try:
            result = future.result(timeout=self.command_timeout)
        except TimeoutError:
            result = CommandResult(False, f'no answer from the link thread within {self.command_timeout:g} s')
            self.get_logger().error(result.message)
        response.success, response.message = result.success, result.message
        return response


def main(args=None):
    """Run the bridge: on a multi-threaded executor, so that waiting services do not hold up the rest, unless
    the mission commands it on /uav/command (then no callback waits).
    """
    built: list[MavlinkBridge] = []

    def build() -> MavlinkBridge:
        built.append(MavlinkBridge())
        return built[0]

    def executor():
        return make_executor() if built[0].commanded else MultiThreadedExecutor()
    sys.exit(run_node(build, args, executor=executor))


if __name__ == '__main__':
    main()
