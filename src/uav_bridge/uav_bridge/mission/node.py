"""ROS 2 node ``mission``: take off, hold station over the boat, land (thesis Sec. 5.3, 5.4).

A thin wrapper around :class:`uav_bridge.mission.logic.MissionLogic`, stepped at ``rate`` on sim
time (lockstep ticks, :mod:`tether_common.lockstep`). It publishes its phase on
``/mission/state`` (tether_msgs/MissionState, transient local) and flies the UAV one request
at a time (mode, arm, takeoff, land; the answer fed to the next step) over one of two links
(``uav_link``):

* ``command`` (the built-in UAV, or ArduPilot SITL on the JSON physics through
  ``mavlink_bridge`` with its ``command_rate``; reproducible): every input is a lockstep input selected by
  stamp. The step at t takes ``/uav/state`` and ``/uav/pose`` stamped ≤ t (no delay) and
  publishes ``/uav/command`` (tether_msgs/UavCommand) stamped t: the latest request with its
  sequence number, and the station as the setpoint while holding. The built-in UAV takes
  that command one mission period P late: a request of the step at t is carried out at the
  UAV's tick t + P, and its outcome (``UavState.command_sequence``) reaches the mission's step
  t + P, the first at which the mission may ask again. That one-period delay is the loop
  mission → UAV → mission's explicit delay. A second task at the reel's control period feeds
  every ``/reel/state`` with the ``/reel/diagnostics`` of the same stamp (no delay) to the trip
  monitor, before the mission step of the same time.
* ``services`` (an autopilot on its own clock through ``mavlink_bridge``): the services ``/uav/set_mode``,
  ``/uav/arm``, ``/uav/takeoff``, ``/uav/land`` and the setpoint on ``/uav/setpoint``
  (geometry_msgs/PoseStamped, ``world``, zero quaternion: heading kept); ``/uav/state``,
  ``/uav/pose``, ``/reel/state`` and ``/reel/diagnostics`` are used as they arrive. The
  autopilot runs on its own clock outside the lockstep, so such a run is not reproducible.
  Each call has a time-out (``service_timeout``, ``arm_service_timeout``) longer than the
  bridge's own: a call unanswered past it ends the mission (:class:`ServiceLink`).

Losing the autopilot in flight (the link down for ``link_grace`` s, a reboot, a disarm) ends
the mission in phase ``lost`` with the reason in ``/mission/state``
(:class:`uav_bridge.mission.logic.AutopilotWatch`; docs/autopilot-link.md).

At the end, with a ``return_speed``, the mission returns over the pad (``pad``, down to
``return_height``), the setpoint on the link as while holding, then lands. A reel trip before the return lands the
UAV where it is (during the return, the return goes on: :mod:`uav_bridge.mission.logic`): the reel in its
fault mode (ReelState.MODE_FAULT: a safety trip holds it, its reason in ``/reel/diagnostics`` ``safety_trip``) for ``abort_after`` s, or a
tension estimate above ``abort_tension`` (:class:`uav_bridge.mission.logic.TripMonitor`). The
mission's landing (the return and the descent) starts at ``land_time``, or
``land_before_end`` s before the end of the run (:func:`tether_common.lockstep.run_end`),
whichever comes first.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from std_srvs.srv import SetBool
from std_srvs.srv import Trigger
from tether_msgs.msg import MissionState
from tether_msgs.msg import ReelControllerDiagnostics
from tether_msgs.msg import ReelState
from tether_msgs.msg import UavCommand
from tether_msgs.msg import UavState
from tether_msgs.srv import SetMode
from tether_msgs.srv import Takeoff

from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.lockstep import run_end
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import COMMAND
from tether_common.qos import LATCHED
from tether_common.qos import LOOP
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from uav_bridge.mission.logic import Inputs
from uav_bridge.mission.logic import MissionConfig
from uav_bridge.mission.logic import MissionLogic
from uav_bridge.mission.logic import TripMonitor
from uav_bridge.mission.params import PARAMETERS

def land_time(params: dict, end: float | None) -> float:
    """The sim time (s) the mission lands at: ``land_time``, or ``land_before_end`` before ``end``, the earlier.

    A run too short for the landing (``end`` ≤ ``land_before_end``) does not land at its end.
    """
    times = [params['land_time'] or math.inf]
    if params['land_before_end'] > 0.0 and end is not None and end > params['land_before_end']:
        times.append(end - params['land_before_end'])
    return min(times)


class MissionNode(Node):
    """Steps the mission logic and carries out its requests."""

    def __init__(self, **options) -> None:
        super().__init__('mission', **options)
        try:
            params = declare_parameters(self, PARAMETERS)
            if len(params['pad']) != 2:
                raise ValueError(f'parameter pad: expected 2 numbers (x, y), got {params["pad"]}')
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        end = run_end()
        if params['land_before_end'] > 0.0 and (end is None or end <= params['land_before_end']):
            why = (f'the run ends at {end:g} s, too soon for a landing' if end is not None
                   else 'the run\'s end is not known (not started by tethersim run)')
            self.get_logger().warning(f'land_before_end {params["land_before_end"]:g} s: {why}; landing only at '
                                      'land_time or on a reel trip')
        self.logic = MissionLogic(MissionConfig(
            altitude=params['altitude'], radial=params['radial'], bearing=math.radians(params['bearing']),
            land_time=land_time(params, end), climb_tolerance=params['climb_tolerance'],
            retry_period=params['retry_period'], pad=tuple(params['pad']), return_speed=params['return_speed'],
            return_height=params['return_height'] or None, return_tolerance=params['return_tolerance'],
            link_grace=params['link_grace']))
        self.abort_tension = params['abort_tension']
        self.trips = TripMonitor(params['abort_after'])
        self.trip_reason = ''
        self.reel_fault = ''
        self.state_pub = self.create_publisher(MissionState, '/mission/state', LATCHED)
        self._published = None
        self.lockstep = Lockstep(self)
        self.link = CommandLink(self, params) if params['uav_link'] == 'command' else ServiceLink(self, params)
        self.lockstep.every(1.0 / params['rate'], self.step, self.link.inputs)
        station = self.logic.station
        self.get_logger().info(f'mission: station {station[2]:g} m up, {math.hypot(*station[:2]):g} m radial '
                               f'(Δr/Δz {math.hypot(*station[:2]) / station[2]:.2f}) in world, over '
                               f'{params["uav_link"]}; '
                               + (f'returns over the pad at {list(params["pad"])} m'
                                  + (f', {params["return_height"]:g} m up,' if params['return_height'] else '')
                                  + f' at {params["return_speed"]:g} m/s and lands' if params['return_speed'] > 0.0
                                  else 'lands')
                               + f' from {self.logic.config.land_time:g} s')

    def reel_state(self, msg: ReelState) -> None:
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
        state, position, busy, answer = self.link.observe(tick)
        inputs = Inputs(
            connected=bool(state and state.connected and not state.stale),
            position_ready=bool(state and state.position_ready), armed=bool(state and state.armed),
            mode=state.mode if state else '', position=position, reel_fault=self.reel_fault,
            busy=busy, answer=answer, reboots=state.reboots if state else 0,
            waiting_for=state.waiting_for if state else '', link_failure=self.link.failure)
        out = self.logic.step(tick.seconds, inputs)
        self.link.send(tick, out.request, out.setpoint)
        if (out.phase, out.reason) != self._published:
            self._published = (out.phase, out.reason)
            self.get_logger().info(f'mission phase {out.phase}' + (f': {out.reason}' if out.reason else ''))
            msg = MissionState()
            msg.header.stamp = tick.stamp
            msg.phase, msg.reason, msg.aborted = out.phase, out.reason, self.logic.aborted
            msg.station.x, msg.station.y, msg.station.z = (float(v) for v in self.logic.station)
            self.state_pub.publish(msg)


def _position(pose: PoseStamped | None) -> np.ndarray | None:
    if pose is None:
        return None
    p = pose.pose.position
    return np.array([p.x, p.y, p.z])


class CommandLink:
    """The built-in UAV over ``/uav/command`` and ``/uav/state``, every input selected by stamp."""

    failure = ''
    """A request left unanswered stops the node (:meth:`observe`): a configuration error, not a lost link."""

    def __init__(self, node: MissionNode, params: dict) -> None:
        self.node = node
        self.inputs = [Input('/uav/state', UavState, 1.0 / params['uav_state_rate'], 0.0, STATE),
                       Input('/uav/pose', PoseStamped, 1.0 / params['uav_pose_rate'], 0.0, SENSOR)]
        self.publisher = node.create_publisher(UavCommand, '/uav/command', LOOP)
        self.command = UavCommand()
        self.command.header.frame_id = 'world'
        self.waiting = False
        self.sent_ns = 0
        self.rate = params['rate']
        self.answer_timeout_ns = round(params['answer_timeout'] * 1e9)
        if params['reel_rate']:
            reel_period = 1.0 / params['reel_rate']
            node.lockstep.every(reel_period, self.reel_step, [
                Input('/reel/state', ReelState, reel_period, 0.0, STATE),
                Input('/reel/diagnostics', ReelControllerDiagnostics, reel_period, 0.0, STATE)])

    def reel_step(self, tick: Tick) -> None:
        """Feed the reel state of this tick, with its diagnostics' trip reason, to the trip monitor."""
        state, diagnostics = tick.inputs['/reel/state'], tick.inputs['/reel/diagnostics']
        if state is None:
            return
        self.node.trip_reason = diagnostics.safety_trip if diagnostics is not None else ''
        self.node.reel_state(state)

    def observe(self, tick: Tick):
        """UAV state, position, whether a request waits for its outcome, and the outcome that came."""
        state = tick.inputs['/uav/state']
        answer = None
        if self.waiting and state is not None and state.command_sequence == self.command.sequence:
            self.waiting = False
            answer = (self.command.request, state.command_success, state.command_message)
        elif self.waiting and tick.time_ns - self.sent_ns > self.answer_timeout_ns:
            raise ConfigurationError(
                f'/uav/state has not answered the {self.command.request} request of /uav/command '
                f'{self.command.sequence} within {self.answer_timeout_ns / 1e9:g} s: run the built-in UAV, or '
                f'mavlink_bridge, with command_rate {self.rate:g} (the mission\'s rate), or an autopilot with '
                'uav_link services')
        return state, _position(tick.inputs['/uav/pose']), self.waiting, answer

    def send(self, tick: Tick, request, setpoint) -> None:
        """Publish this step's command: a new request under the next sequence number, the setpoint."""
        command = self.command
        if request is not None:
            kind, value = request
            command.sequence += 1
            command.request = kind
            command.mode = str(value) if kind == 'set_mode' else ''
            command.arm = bool(value) if kind == 'arm' else False
            command.altitude = float(value) if kind == 'takeoff' else 0.0
            self.waiting = True
            self.sent_ns = tick.time_ns
        command.header.stamp = tick.stamp
        command.hold = setpoint is not None
        if setpoint is not None:
            command.setpoint.x, command.setpoint.y, command.setpoint.z = (float(v) for v in setpoint)
        self.publisher.publish(command)


class ServiceLink:
    """An autopilot through the MAVLink bridge's services; its state and the reel's as they arrive.

    Each call has a time-out (``service_timeout``, ``arm_service_timeout`` for arming): longer
    than the bridge's own command and arm time-outs, within which the bridge answers every call
    (or refuses it, with the autopilot's reasons), so a call unanswered past it means the bridge
    is gone or hung (a lost answer: rclpy never ends a call whose server vanished). It counts
    on both clocks, the wall clock of the bridge's time-outs and the sim time of the graph, so a
    graph slower than real time with a bridge in the lockstep (its time-outs on sim time) still
    gets its answer. The time-out is logged in one line and ends the mission (``failure``: phase
    ``lost``, the reason in ``/mission/state``); a late answer is then ignored.
    """

    inputs: tuple[Input, ...] = ()

    def __init__(self, node: MissionNode, params: dict) -> None:
        self.node = node
        self.uav_state: UavState | None = None
        self.position: np.ndarray | None = None
        self.pending: str | None = None
        self.answer = None
        self.failure = ''
        self.timeouts = {kind: params['service_timeout'] for kind in ('set_mode', 'takeoff', 'land')}
        self.timeouts['arm'] = params['arm_service_timeout']
        self._called: tuple[float, float] = (0.0, 0.0)     # (wall clock s, sim time s) of the call out
        node.create_subscription(UavState, '/uav/state', self._on_state, LATCHED)
        node.create_subscription(PoseStamped, '/uav/pose', self._on_pose, SENSOR)
        node.create_subscription(ReelState, '/reel/state', node.reel_state, STATE)
        node.create_subscription(ReelControllerDiagnostics, '/reel/diagnostics', self._on_diagnostics, STATE)
        self.setpoint_pub = node.create_publisher(PoseStamped, '/uav/setpoint', COMMAND)
        self.clients = {'set_mode': (node.create_client(SetMode, '/uav/set_mode'), lambda v: SetMode.Request(mode=v)),
                        'arm': (node.create_client(SetBool, '/uav/arm'), lambda v: SetBool.Request(data=v)),
                        'takeoff': (node.create_client(Takeoff, '/uav/takeoff'),
                                    lambda v: Takeoff.Request(altitude=float(v))),
                        'land': (node.create_client(Trigger, '/uav/land'), lambda v: Trigger.Request())}

    def _on_state(self, msg: UavState) -> None:
        self.uav_state = msg

    def _on_pose(self, msg: PoseStamped) -> None:
        self.position = _position(msg)

    def _on_diagnostics(self, msg: ReelControllerDiagnostics) -> None:
        self.node.trip_reason = msg.safety_trip

    def observe(self, tick: Tick):
        """The latest UAV state and position, whether a call is out, and the answer that came since the last step."""
        answer, self.answer = self.answer, None
        pending = self.pending
        if pending is not None and not self.failure:
            limit = self.timeouts[pending]
            wall, sim = time.monotonic() - self._called[0], tick.seconds - self._called[1]
            if wall >= limit and sim >= limit:
                name = self.clients[pending][0].srv_name
                self.failure = (f'no answer from {name} within {limit:g} s ({wall:.1f} s wall, {sim:.1f} s sim): the '
                                'bridge answers every call within its own time-outs, so it is gone or hung')
                self.node.get_logger().error(f'{pending}: {self.failure}')
        return self.uav_state, self.position, pending is not None, answer

    def send(self, tick: Tick, request, setpoint) -> None:
        """Call the request's service; publish the setpoint."""
        if request is not None:
            self._call(*request, tick.seconds)
        if setpoint is not None:
            msg = PoseStamped()
            msg.header.stamp, msg.header.frame_id = tick.stamp, 'world'
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = (float(v) for v in setpoint)
            msg.pose.orientation.w = 0.0
            self.setpoint_pub.publish(msg)

    def _call(self, kind: str, value, now: float) -> None:
        client, build = self.clients[kind]
        if not client.service_is_ready():
            self.answer = (kind, False, f'service of {kind} not available')
            return
        self.pending = kind
        self._called = (time.monotonic(), now)
        future = client.call_async(build(value))
        future.add_done_callback(lambda done: self._answered(kind, done))

    def _answered(self, kind: str, future) -> None:
        if self.failure:
            return
        self.pending = None
        error = future.exception()
        self.answer = (kind, False, str(error)) if error else (kind, future.result().success, future.result().message)


def main(args=None):
    """Run the mission node."""
    sys.exit(run_node(MissionNode, args))


if __name__ == '__main__':
    main()
