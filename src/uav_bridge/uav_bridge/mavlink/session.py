"""The MAVLink session with one autopilot: connection, streams, commands (no rclpy).

:class:`MavlinkSession` owns the link in its own thread, so a ROS executor is never blocked
by I/O. It

* connects to the URL (:mod:`uav_bridge.mavlink.transport`) and reconnects with exponential back-off
  after a failure, an EOF, or a silence of twice the link timeout;
* sends its own HEARTBEAT (a GCS/onboard computer) every ``heartbeat_period``;
* asks for the telemetry it converts with MAV_CMD_SET_MESSAGE_INTERVAL (511) when the link
  comes up, resumes after a gap, or the autopilot rebooted, and again, with back-off, for
  any stream that has not arrived within ``stream_timeout`` (ArduPilot forgets requested
  intervals when it restarts, and sends LOCAL_POSITION_NED only once its EKF uses GPS);
* tracks the autopilot (:class:`uav_bridge.mavlink.autopilot_state.AutopilotState`) and hands
  converted samples (:mod:`uav_bridge.mavlink.telemetry`) with the caller's clock's stamp to
  ``on_sample``, and a :class:`LinkStatus` to ``on_status`` (if given) on every change and
  every ``status_period`` (:meth:`MavlinkSession.status` builds one on demand);
* runs commands (mode, arm, disarm, takeoff, land) submitted from other threads, each
  answering a :class:`concurrent.futures.Future` with :class:`CommandResult`: arming is
  retried with back-off while the autopilot refuses, the STATUSTEXT reasons collected;
* sends position setpoints as SET_POSITION_TARGET_LOCAL_NED as they come.

Bytes that are not MAVLink, unknown messages and failing callbacks are counted and logged,
never fatal. Link times are wall time (``clock``, monotonic s); sample stamps come from
``stamp_clock`` (the graph's clock in a node).

**Stepped mode** (``start(stepped=True)``): for an autopilot in the graph's lockstep (SITL
on the JSON physics, which answers its frames only inside the graph's ticks). The thread
then only opens the link (connection attempts back off in wall time: SITL's clock stands
still until a client is connected, so when the link opens does not change the flight); the
caller does everything else in :meth:`poll` with its sim time: read what the autopilot sent,
run every timer (HEARTBEAT, stream requests, command resends, arming retries, staleness) on
that time and send. Called while SITL waits for its next physics frame, every byte sent
reaches SITL at the same frame whatever the wall-clock pace: the same flight at any speed.
"""

from __future__ import annotations

import os
import queue
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from dataclasses import field

os.environ.setdefault('MAVLINK20', '1')

from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

from uav_bridge.mavlink import telemetry  # noqa: E402
from uav_bridge.mavlink.autopilot_state import AutopilotState  # noqa: E402
from uav_bridge.mavlink.transport import LinkClosed  # noqa: E402
from uav_bridge.mavlink.transport import Transport  # noqa: E402
from uav_bridge.mavlink.transport import parse_url  # noqa: E402

MAV_CMD_SET_MESSAGE_INTERVAL = 511
MAV_CMD_DO_SET_MODE = 176
MAV_CMD_COMPONENT_ARM_DISARM = 400
MAV_CMD_NAV_TAKEOFF = 22
MAV_CMD_NAV_LAND = 21
MAV_RESULT_ACCEPTED = 0
MAV_RESULT_IN_PROGRESS = 5
MAV_MODE_FLAG_CUSTOM_MODE_ENABLED = 1
MAV_TYPE_ONBOARD_CONTROLLER = 18
MAV_AUTOPILOT_INVALID = 8
MAV_STATE_ACTIVE = 4
MAV_COMP_ID_ONBOARD_COMPUTER = 191
RESULT_NAMES = {0: 'accepted', 1: 'temporarily rejected', 2: 'denied', 3: 'unsupported', 4: 'failed',
                5: 'in progress', 6: 'cancelled'}

STREAM_IDS = {
    'ATTITUDE': mavlink.MAVLINK_MSG_ID_ATTITUDE,
    'LOCAL_POSITION_NED': mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED,
    'HIGHRES_IMU': mavlink.MAVLINK_MSG_ID_HIGHRES_IMU,
    'GLOBAL_POSITION_INT': mavlink.MAVLINK_MSG_ID_GLOBAL_POSITION_INT,
    'EKF_STATUS_REPORT': mavlink.MAVLINK_MSG_ID_EKF_STATUS_REPORT,
}
"""The messages the bridge converts, by name, with their MAVLink ids."""


@dataclass
class SessionConfig:
    """Settings of a session; times are wall-clock seconds."""

    url: str = 'tcp:127.0.0.1:5760'
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)   # m, EKF origin in world (ENU)
    system_id: int = 255
    component_id: int = MAV_COMP_ID_ONBOARD_COMPUTER
    heartbeat_period: float = 1.0
    link_timeout: float = 3.0
    reconnect_min: float = 0.5
    reconnect_max: float = 8.0
    stream_rates: dict[str, float] = field(default_factory=lambda: {
        'ATTITUDE': 50.0, 'LOCAL_POSITION_NED': 50.0, 'HIGHRES_IMU': 50.0, 'GLOBAL_POSITION_INT': 10.0,
        'EKF_STATUS_REPORT': 2.0})   # Hz of autopilot time
    stream_timeout: float = 3.0
    status_period: float = 1.0
    command_timeout: float = 5.0
    command_resend: float = 1.0
    arm_timeout: float = 120.0
    arm_retry_min: float = 1.0
    arm_retry_max: float = 8.0
    statustext_lines: int = 10


@dataclass(frozen=True)
class CommandResult:
    """Outcome of a command."""

    success: bool
    message: str


@dataclass(frozen=True)
class LinkStatus:
    """The link and autopilot state handed to ``on_status``."""

    stamp: float
    connected: bool
    stale: bool
    armed: bool
    """As of the latest HEARTBEAT while connected; False while the link is closed or stale (nothing is known of a
    silent autopilot, which may be rebooting)."""
    mode: str
    """As :attr:`armed`: '' while the link is closed or stale."""
    ready: bool
    position_ready: bool
    ekf_flags: int
    waiting_for: str
    heartbeat_age: float
    time_offset: float
    reconnects: int
    reboots: int
    bad_packets: int
    status_text: tuple[str, ...]

    def key(self) -> tuple:
        """The fields whose change is published at once (ages and offsets are not)."""
        return (self.connected, self.stale, self.armed, self.mode, self.ready, self.position_ready,
                self.ekf_flags, self.waiting_for, self.reconnects, self.reboots, self.status_text)


@dataclass
class _Command:
    kind: str
    future: Future
    timeout: float
    argument: float | str | None = None
    deadline: float = 0.0
    next_send: float = 0.0
    attempts: int = 0
    backoff: float = 0.0
    status_serial: int = 0
    reasons: list[str] = field(default_factory=list)
    acked: bool = False


class MavlinkSession:
    """One MAVLink link to an autopilot, run in a background thread (see the module docstring)."""

    def __init__(self, config: SessionConfig,
                 on_sample: Callable[[object, float], None] = lambda sample, stamp: None,
                 on_status: Callable[[LinkStatus], None] | None = None,
                 log: Callable[[str, str], None] = lambda level, text: None,
                 clock: Callable[[], float] = time.monotonic,
                 stamp_clock: Callable[[], float] = time.monotonic) -> None:
        self.config = config
        self.endpoint = parse_url(config.url)
        unknown = sorted(set(config.stream_rates) - set(STREAM_IDS))
        if unknown:
            raise ValueError(f'unknown telemetry streams {unknown}, known: {sorted(STREAM_IDS)}')
        self.on_sample = on_sample
        self.on_status = on_status
        self.log = log
        self.clock = clock
        self.stamp_clock = stamp_clock
        self.state = AutopilotState(config.link_timeout, config.statustext_lines, own_system=config.system_id)
        self.stream_requests = {name: 0 for name in config.stream_rates}
        self.stream_acks: dict[str, int] = {}
        self._encoder = mavlink.MAVLink(None, config.system_id, config.component_id)
        self._parser = self._new_parser()
        self._transport: Transport | None = None
        self._next_connect = 0.0
        self._connect_backoff = config.reconnect_min
        self._last_error = ''
        self._next_heartbeat = 0.0
        self._stream_next = {name: 0.0 for name in config.stream_rates}
        self._stream_backoff = {name: config.stream_timeout for name in config.stream_rates}
        self._stream_since = {name: 0.0 for name in config.stream_rates}
        self._stream_force: set[str] = set()
        self._attitude: telemetry.Attitude | None = None
        self._time_offset = float('nan')
        self._last_status_key: tuple | None = None
        self._next_status = 0.0
        self._was_stale = True
        self._commands: queue.Queue[_Command | telemetry.PositionTarget] = queue.Queue()
        self._active: _Command | None = None
        self._pending: list[_Command] = []
        self._connected_at = 0.0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.setpoints_sent = 0
        self.callback_errors = 0

    # thread control

    def start(self, stepped: bool = False) -> None:
        """Run the link in a daemon thread; ``stepped``: the thread only connects, :meth:`poll` does the rest."""
        self._thread = threading.Thread(target=self._connect_loop if stepped else self._run, name='mavlink',
                                        daemon=True)
        self._thread.start()

    def poll(self, now: float) -> None:
        """Stepped mode: handle everything received so far, then run the timers at ``now`` and send."""
        while self._transport is not None and self._transport.wait_readable(0.0):
            try:
                data = self._transport.recv()
            except LinkClosed as error:
                self._close(str(error))
                break
            self._receive(data, now)
        self._advance(now)

    def stop(self) -> None:
        """Stop the thread, fail pending commands, close the link."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
        self._close('the bridge stopped', reconnect=False)
        pending = ([self._active] if self._active else []) + self._pending
        while not self._commands.empty():
            pending.append(self._commands.get_nowait())
        for command in pending:
            if isinstance(command, _Command) and not command.future.done():
                command.future.set_result(CommandResult(False, 'the bridge stopped'))

    # requests from other threads

    def set_mode(self, name: str) -> Future:
        """Ask for flight mode ``name``; done when the HEARTBEAT shows it."""
        return self._submit('mode', name.upper(), self.config.command_timeout)

    def arm(self, arm: bool = True) -> Future:
        """Arm (retried with back-off while refused, up to ``arm_timeout``) or disarm."""
        if arm:
            return self._submit('arm', None, self.config.arm_timeout)
        return self._submit('disarm', None, self.config.command_timeout)

    def takeoff(self, altitude: float) -> Future:
        """Take off to ``altitude`` m above the take-off point (armed, in GUIDED)."""
        return self._submit('takeoff', float(altitude), self.config.command_timeout)

    def land(self) -> Future:
        """Land where the UAV is (MAV_CMD_NAV_LAND)."""
        return self._submit('land', None, self.config.command_timeout)

    def send_setpoint(self, position_world, yaw_ned: float | None = None) -> None:
        """Queue a position target in ``world`` (ENU, m), with a NED heading (rad) or none."""
        self._commands.put(telemetry.position_target(position_world, self.config.origin, yaw_ned))

    def _submit(self, kind: str, argument, timeout: float) -> Future:
        future: Future = Future()
        self._commands.put(_Command(kind, future, timeout, argument))
        return future

    # the loop

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                self._step()
            except Exception as error:  # noqa: BLE001 - the link thread must survive anything
                self.callback_errors += 1
                self._stop.wait(0.05)
                try:
                    self.log('error', f'link step failed: {type(error).__name__}: {error}')
                except Exception:  # noqa: BLE001 - nor a logger that fails
                    continue

    def _connect_loop(self) -> None:
        while not self._stop.is_set():
            if self._transport is None:
                self._try_connect()
            self._stop.wait(0.02 if self._transport is None else 0.1)

    def _try_connect(self) -> None:
        """Open the link unless the back-off (wall time: the OS and the process, not the autopilot) waits."""
        wall = time.monotonic()
        if wall >= self._next_connect:
            self._connect(self.clock())
            if self._transport is None:
                self._next_connect = wall + self._connect_backoff
                self._connect_backoff = min(2.0 * self._connect_backoff, self.config.reconnect_max)

    def _step(self) -> None:
        if self._transport is None:
            self._try_connect()
            if self._transport is None:
                self._advance(self.clock())
                self._stop.wait(min(0.05, max(0.0, self._next_connect - time.monotonic())))
                return
        if self._transport.wait_readable(0.01):
            try:
                data = self._transport.recv()
            except LinkClosed as error:
                self._close(str(error))
                return
            self._receive(data, self.clock())
        self._advance(self.clock())

    def _connect(self, now: float) -> None:
        try:
            transport = Transport.open(self.endpoint)
        except OSError as error:
            reason = error.strerror or str(error)
            if reason != self._last_error:
                self.log('info', f'waiting for the autopilot on {self.endpoint}: {reason}; '
                                 f'retrying with back-off up to {self.config.reconnect_max:g} s')
            self._last_error = reason
            return
        self._last_error = ''
        self._parser = self._new_parser()
        self.state.connection_made()
        self._connected_at = now
        self._next_heartbeat = now
        self._transport = transport         # last: in stepped mode, poll() uses the link from here on
        self.log('info', f'link open on {self.endpoint}, waiting for a HEARTBEAT')

    def _close(self, reason: str, reconnect: bool = True) -> None:
        if self._transport is None:
            return
        self._transport.close()
        self._transport = None
        self.state.connection_lost()
        self._was_stale = True          # 'link lost' says it: no 'link stale' line after it
        self._next_connect = time.monotonic() + self._connect_backoff
        if reconnect:
            self.log('warn', f'link lost: {reason}; reconnecting with back-off up to {self.config.reconnect_max:g} s')

    def _new_parser(self):
        parser = mavlink.MAVLink(None, 0, 0)
        parser.robust_parsing = True
        return parser

    def _send(self, msg) -> None:
        if self._transport is None:
            return
        try:
            self._transport.send(msg.pack(self._encoder))
        except LinkClosed as error:
            self._close(str(error))

    # receiving

    def _receive(self, data: bytes, now: float) -> None:
        try:
            messages = self._parser.parse_buffer(data) or []
        except Exception:  # noqa: BLE001 - pymavlink raises on some malformed frames
            self.state.on_bad_data()
            self._parser = self._new_parser()
            return
        for msg in messages:
            if msg.get_type() == 'BAD_DATA':
                self.state.on_bad_data()
                continue
            self._handle(msg, now)

    def _handle(self, msg, now: float) -> None:
        events = self.state.on_message(msg, now)
        if not self.state.accepts(msg):
            return
        stamp = self.stamp_clock()
        seconds = getattr(msg, 'time_boot_ms', None)
        if seconds is not None:
            self._time_offset = stamp - seconds * 1e-3
        for event in events:
            self._on_event(event, now)
        kind = msg.get_type()
        if kind in self._stream_backoff:
            self._stream_backoff[kind] = self.config.stream_timeout
        if kind == 'ATTITUDE':
            self._attitude = telemetry.attitude(msg)
        elif kind == 'LOCAL_POSITION_NED' and self._attitude is not None:
            self._emit(telemetry.kinematics(msg, self._attitude, self.config.origin), stamp)
        elif kind == 'HIGHRES_IMU' and self._attitude is not None:
            self._emit(telemetry.imu(msg, self._attitude), stamp)
        elif kind == 'GLOBAL_POSITION_INT':
            self._emit(telemetry.global_fix(msg), stamp)
        elif kind == 'STATUSTEXT':
            self.log('info', f'autopilot: {msg.text}')
        elif kind == 'COMMAND_ACK':
            self._on_ack(msg, now)

    def _emit(self, sample, stamp: float) -> None:
        try:
            self.on_sample(sample, stamp)
        except Exception as error:  # noqa: BLE001 - a failing consumer must not stop the link
            self.callback_errors += 1
            self.log('error', f'sample callback failed: {type(error).__name__}: {error}')

    def _on_event(self, event: str, now: float) -> None:
        texts = {'link_up': 'autopilot heard (system {sid}); requesting telemetry streams',
                 'resumed': 'HEARTBEAT back after a gap; requesting telemetry streams again',
                 'reboot': 'autopilot rebooted (time since boot went backwards); requesting telemetry streams again'}
        self.log('warn' if event != 'link_up' else 'info', texts[event].format(sid=self.state.system_id))
        self._connect_backoff = self.config.reconnect_min
        self._attitude = None if event == 'reboot' else self._attitude
        self._stream_force = set(self._stream_next)
        for name in self._stream_next:
            self._stream_backoff[name] = self.config.stream_timeout
            self._stream_since[name] = now

    def _on_ack(self, msg, now: float) -> None:
        if msg.command == MAV_CMD_SET_MESSAGE_INTERVAL:
            return
        command = self._active
        if command is None or msg.command != _COMMAND_IDS.get(command.kind):
            return
        if msg.result == MAV_RESULT_IN_PROGRESS:
            return
        if msg.result == MAV_RESULT_ACCEPTED:
            command.acked = True
            if command.kind in ('takeoff', 'land'):
                self._finish(CommandResult(True, f'{command.kind} accepted'))
            return
        reason = f'{command.kind} {RESULT_NAMES.get(msg.result, f"result {msg.result}")}'
        command.reasons.append(reason)
        if command.kind == 'arm':
            command.next_send = now + command.backoff
            command.backoff = min(2.0 * command.backoff, self.config.arm_retry_max)
            return
        self._finish(CommandResult(False, self._explain(command, reason)))

    # periodic work

    def _advance(self, now: float) -> None:
        connected = self._transport is not None
        if connected and now >= self._next_heartbeat:
            self._send(self._encoder.heartbeat_encode(MAV_TYPE_ONBOARD_CONTROLLER, MAV_AUTOPILOT_INVALID, 0, 0,
                                                      MAV_STATE_ACTIVE))
            self._next_heartbeat = now + self.config.heartbeat_period
        stale = self.state.stale(now)
        if stale and not self._was_stale and self.state.last_heartbeat is not None:
            self.log('warn', f'link stale: no HEARTBEAT for {self.config.link_timeout:g} s')
        self._was_stale = stale
        if connected and self._silent_too_long(now):
            self._close(f'no HEARTBEAT for {2 * self.config.link_timeout:g} s')
        if self._transport is not None and not stale:
            self._request_streams(now)
        self._take_commands(now)
        if self._active is not None:
            self._advance_command(now)
        self._publish_status(now)

    def _silent_too_long(self, now: float) -> bool:
        last = self.state.last_heartbeat
        heard = last is not None and last >= self._connected_at
        return now - (last if heard else self._connected_at) > 2.0 * self.config.link_timeout

    def _request_streams(self, now: float) -> None:
        for name, rate in self.config.stream_rates.items():
            seen = self.state.last_seen.get(name)
            fresh = seen is not None and now - seen <= self.config.stream_timeout and seen >= self._stream_since[name]
            if name not in self._stream_force and (fresh or now < self._stream_next[name]):
                continue
            self._stream_force.discard(name)
            self._send(self._encoder.command_long_encode(
                self.state.system_id, self.state.component_id or 1, MAV_CMD_SET_MESSAGE_INTERVAL, 0,
                STREAM_IDS[name], 1e6 / rate, 0, 0, 0, 0, 0))
            self.stream_requests[name] += 1
            self._stream_next[name] = now + self._stream_backoff[name]
            self._stream_backoff[name] = min(2.0 * self._stream_backoff[name], 4.0 * self.config.stream_timeout)

    def missing_streams(self, now: float) -> list[str]:
        """Requested streams (other than LOCAL_POSITION_NED) not arriving."""
        return [name for name in self.config.stream_rates if name != 'LOCAL_POSITION_NED'
                and (self.state.last_seen.get(name) is None
                     or now - self.state.last_seen[name] > self.config.stream_timeout)]

    def _take_commands(self, now: float) -> None:
        while True:
            try:
                item = self._commands.get_nowait()
            except queue.Empty:
                break
            if isinstance(item, telemetry.PositionTarget):
                self._send_target(item, now)
            else:
                self._pending.append(item)
        if self._active is None and self._pending:
            self._start(self._pending.pop(0), now)

    def _send_target(self, target: telemetry.PositionTarget, now: float) -> None:
        if self.state.stale(now) or self.state.system_id is None:
            return
        self._send(self._encoder.set_position_target_local_ned_encode(
            int(self.state.boot_time * 1000) if self.state.boot_time else 0,
            self.state.system_id, self.state.component_id or 1, target.coordinate_frame, target.type_mask,
            target.x, target.y, target.z, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, target.yaw, 0.0))
        self.setpoints_sent += 1

    def _start(self, command: _Command, now: float) -> None:
        command.deadline = now + command.timeout
        command.status_serial = self.state.status_serial
        command.backoff = self.config.arm_retry_min
        self._active = command

    def _advance_command(self, now: float) -> None:
        command = self._active
        state = self.state
        if command.kind == 'mode':
            number = state.mode_number(command.argument) if state.mav_type is not None else None
            if state.mav_type is not None and number is None:
                self._finish(CommandResult(False, f'unknown mode {command.argument!r} for this vehicle; known: '
                                                  + ', '.join(state.mode_names())))
                return
            if not state.stale(now) and state.custom_mode == number and command.attempts:
                self._finish(CommandResult(True, f'mode {command.argument}'))
                return
        elif command.kind == 'arm' and state.armed and not state.stale(now):
            self._finish(CommandResult(True, 'armed' + (f' after {command.attempts} attempts'
                                                        if command.attempts > 1 else '')))
            return
        elif command.kind == 'disarm' and not state.armed and not state.stale(now) and command.attempts:
            self._finish(CommandResult(True, 'disarmed'))
            return
        if now >= command.deadline:
            what = {'arm': f'not armed after {command.attempts} attempts'}.get(command.kind, 'no answer')
            if state.stale(now):
                what = f'link stale ({state.waiting_for(now, str(self.endpoint), [])})'
            self._finish(CommandResult(False, self._explain(command, f'{command.kind}: {what}')))
            return
        if now < command.next_send or state.stale(now) or state.system_id is None:
            return
        self._send_command(command)
        command.attempts += 1
        command.next_send = now + self.config.command_resend
        if command.kind == 'arm' and command.attempts > 1:
            self.log('info', f'arming, attempt {command.attempts}; refused before: {self._reasons(command)}')

    def _send_command(self, command: _Command) -> None:
        state = self.state
        params = [0.0] * 7
        if command.kind == 'mode':
            params[0], params[1] = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, state.mode_number(command.argument)
        elif command.kind in ('arm', 'disarm'):
            params[0] = 1.0 if command.kind == 'arm' else 0.0
        elif command.kind == 'takeoff':
            params[6] = command.argument
        self._send(self._encoder.command_long_encode(state.system_id, state.component_id or 1,
                                                     _COMMAND_IDS[command.kind], 0, *params))

    def _finish(self, result: CommandResult) -> None:
        command = self._active
        self._active = None
        level = 'info' if result.success else 'warn'
        self.log(level, f'{command.kind}: {result.message}')
        if not command.future.done():
            command.future.set_result(result)

    def _reasons(self, command: _Command) -> str:
        texts = list(dict.fromkeys(command.reasons + self.state.warnings_since(command.status_serial)))
        return '; '.join(texts[-6:]) if texts else 'no reason given'

    def _explain(self, command: _Command, what: str) -> str:
        return f'{what}; autopilot said: {self._reasons(command)}'

    def _publish_status(self, now: float) -> None:
        if self.on_status is None:  # nobody takes pushed statuses (a stepped consumer asks for one at its ticks)
            return
        status = self.status(now)
        key = status.key()
        if key == self._last_status_key and now < self._next_status:
            return
        self._last_status_key = key
        self._next_status = now + self.config.status_period
        try:
            self.on_status(status)
        except Exception as error:  # noqa: BLE001 - a failing consumer must not stop the link
            self.callback_errors += 1
            self.log('error', f'status callback failed: {type(error).__name__}: {error}')

    def status(self, now: float) -> LinkStatus:
        """The current :class:`LinkStatus`."""
        state = self.state
        position_ready = state.position_ready(now)
        connected = self._transport is not None and not state.stale(now)
        return LinkStatus(
            stamp=self.stamp_clock(), connected=connected, stale=state.stale(now),
            armed=state.armed and connected, mode=state.mode if connected else '',
            ready=state.armed and state.mode.startswith('GUIDED') and position_ready and connected,
            position_ready=position_ready, ekf_flags=state.ekf_flags,
            waiting_for=state.waiting_for(now, str(self.endpoint), self.missing_streams(now)),
            heartbeat_age=state.heartbeat_age(now), time_offset=self._time_offset,
            reconnects=state.reconnects, reboots=state.reboots, bad_packets=state.bad_packets,
            status_text=tuple(state.status_text))


_COMMAND_IDS = {'mode': MAV_CMD_DO_SET_MODE, 'arm': MAV_CMD_COMPONENT_ARM_DISARM,
                'disarm': MAV_CMD_COMPONENT_ARM_DISARM, 'takeoff': MAV_CMD_NAV_TAKEOFF, 'land': MAV_CMD_NAV_LAND}
