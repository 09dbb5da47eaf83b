"""Test double of ArduCopter over MAVLink: an in-process TCP peer for the bridge's tests.

:class:`ArduCopterPeerDouble` reproduces what ``../shared/notes/ardupilot-sitl-mavlink.md``
and ``../shared/sitl/README.md`` observed of a real ArduCopter SITL, in simulated time
running ``speedup`` times wall time:

* nothing runs until a client connects; then HEARTBEAT at 1 Hz, boot STATUSTEXT lines, some
  PARAM_VALUE, and a few bytes of console text that are not MAVLink;
* telemetry only when asked for with MAV_CMD_SET_MESSAGE_INTERVAL (acknowledged, result 0);
* LOCAL_POSITION_NED only after the EKF uses GPS (``ekf_delay`` s after boot, announced by
  "EKF3 IMU0 is using GPS"); GLOBAL_POSITION_INT carries lat = lon = 0 before;
* the default RC input switches the mode to STABILIZE ``rc_mode_switch`` s after boot;
* arming refused before the EKF is ready: COMMAND_ACK result 4 and STATUSTEXT
  "PreArm: Need Position Estimate";
* GUIDED: MAV_CMD_NAV_TAKEOFF (armed only), SET_POSITION_TARGET_LOCAL_NED (one-shot
  targets, position and yaw bits of the type mask); MAV_CMD_NAV_LAND lands and disarms;
* :meth:`reboot` restarts the boot clock and forgets the requested streams,
  :meth:`drop_link` closes the connection and refuses new ones for a while,
  :meth:`silence` stops sending while the connection stays open,
  :meth:`send_garbage` writes bytes that are not valid MAVLink.

The vehicle is a point that moves toward its target at a limited speed; attitude is level
unless :meth:`set_state` pins a pose (used for the conversion checks).
"""

from __future__ import annotations

import math
import os
import select
import socket
import threading
import time

import numpy as np

os.environ.setdefault('MAVLINK20', '1')

from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

GRAVITY = 9.80665
COPTER_MODES = {'STABILIZE': 0, 'ALT_HOLD': 2, 'AUTO': 3, 'GUIDED': 4, 'LOITER': 5, 'RTL': 6, 'LAND': 9,
                'POSHOLD': 16, 'BRAKE': 17}
HOME = (-35.363262, 149.165237, 584.0)


class ArduCopterPeerDouble:
    """A TCP MAVLink peer on 127.0.0.1 behaving like ArduCopter SITL (see the module docstring)."""

    def __init__(self, speedup: float = 5.0, ekf_delay: float = 10.0, rc_mode_switch: float = 2.5,
                 seed: int = 0, port: int = 0) -> None:
        self.speedup = speedup
        self.ekf_delay = ekf_delay
        self.rc_mode_switch = rc_mode_switch
        self.rng = np.random.default_rng(seed)
        self.lock = threading.RLock()
        self.listener = self._listen(port)
        self.port = self.listener.getsockname()[1]
        self.client: socket.socket | None = None
        self.mav = mavlink.MAVLink(None, 1, 1)
        self.parser = mavlink.MAVLink(None, 0, 0)
        self.parser.robust_parsing = True
        self.received: list[tuple[float, object]] = []   # (wall time, message) from the client
        self.interval_requests: list[tuple[float, int, float]] = []   # (wall time, msg id, interval µs)
        self.connections = 0
        self.boots = 0
        self.booted = False
        self._refuse_until = 0.0
        self._silent_until = 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name='peer', daemon=True)
        self._reset_vehicle()

    # control from the test

    def start(self) -> ArduCopterPeerDouble:
        """Serve in a background thread."""
        self._thread.start()
        return self

    def close(self) -> None:
        """Stop serving and close every socket."""
        self._stop.set()
        self._thread.join(timeout=5.0)
        with self.lock:
            self._drop_client()
            if self.listener is not None:
                self.listener.close()
                self.listener = None

    def sim_time(self) -> float:
        """Simulated seconds since boot (0 before the first client)."""
        with self.lock:
            return self._sim_time(time.monotonic())

    def reboot(self) -> None:
        """Restart the autopilot behind an open link: boot clock from 0, streams forgotten."""
        with self.lock:
            self._reset_vehicle()
            self._boot(time.monotonic())

    def drop_link(self, seconds: float) -> None:
        """Close the connection and refuse new ones for ``seconds`` of wall time (state kept)."""
        with self.lock:
            self._drop_client()
            self._refuse_until = time.monotonic() + seconds
            self.listener.close()
            self.listener = None

    def silence(self, seconds: float) -> None:
        """Send nothing for ``seconds`` of wall time; the connection stays open."""
        with self.lock:
            self._silent_until = time.monotonic() + seconds

    def send_garbage(self, count: int = 2000) -> int:
        """Write random bytes, corrupted and truncated frames; return the bytes written."""
        good = self.mav.heartbeat_encode(2, 3, 89, 0, 3).pack(self.mav)
        corrupted = bytearray(good)
        corrupted[-1] ^= 0xFF
        text = bytearray(self.mav.statustext_encode(6, b'x' * 50).pack(self.mav))
        text[12:20] = b'\xff\xfe\xfd\xfc\x00\x80\x81\x82'
        junk = (self.rng.integers(0, 256, count, dtype=np.uint8).tobytes() + bytes(corrupted)
                + good[:7] + bytes([0xFD, 0xFF, 0, 0, 0, 1, 1, 0xFF, 0xFF, 0xFF]) + bytes(text)
                + b'\xfe' * 50 + b'\xfd' * 50)
        with self.lock:
            self._write(junk)
        return len(junk)

    def set_state(self, position, velocity, roll: float, pitch: float, yaw: float, rates=(0.0, 0.0, 0.0)) -> None:
        """Pin the vehicle's NED position (m), velocity (m/s), attitude (rad) and FRD rates (rad/s)."""
        with self.lock:
            self.position = np.array(position, dtype=float)
            self.velocity = np.array(velocity, dtype=float)
            self.attitude = np.array([roll, pitch, yaw], dtype=float)
            self.rates = np.array(rates, dtype=float)
            self.pinned = True

    def requests_since(self, wall: float) -> set[int]:
        """Message ids whose interval the client requested after wall time ``wall``."""
        with self.lock:
            return {msg_id for t, msg_id, _ in self.interval_requests if t >= wall}

    def snapshot(self) -> dict:
        """The vehicle's state (NED position, armed, mode name, EKF ready, sim time)."""
        with self.lock:
            now = time.monotonic()
            return {'position': self.position.copy(), 'armed': self.armed, 'mode': self._mode_name(),
                    'ekf_ready': self._ekf_ready(now), 'sim_time': self._sim_time(now), 'boots': self.boots}

    # vehicle

    def _reset_vehicle(self) -> None:
        self.position = np.zeros(3)
        self.velocity = np.zeros(3)
        self.attitude = np.zeros(3)
        self.rates = np.zeros(3)
        self.target = None
        self.target_yaw = None
        self.pinned = False
        self.armed = False
        self.mode = COPTER_MODES['STABILIZE']
        self.intervals: dict[int, float] = {}
        self.next_due: dict[int, float] = {}
        self.landed_since: float | None = None
        self.booted = False
        self.boot_wall = 0.0
        self.last_sim = 0.0
        self.events_done: set[str] = set()

    def _boot(self, wall: float) -> None:
        self.booted = True
        self.boots += 1
        self.boot_wall = wall
        self.last_sim = 0.0
        self._write(b'\n\nInit ArduCopter V4.8.0-dev (test double)\n')

    def _sim_time(self, wall: float) -> float:
        return (wall - self.boot_wall) * self.speedup if self.booted else 0.0

    def _ekf_ready(self, wall: float) -> bool:
        return self.booted and self._sim_time(wall) >= self.ekf_delay

    def _mode_name(self) -> str:
        return {v: k for k, v in COPTER_MODES.items()}.get(self.mode, f'MODE({self.mode})')

    def _step_vehicle(self, t: float, dt: float) -> None:
        if self.pinned or not self.armed:
            return
        if self.mode == COPTER_MODES['LAND']:
            self.target = np.array([self.position[0], self.position[1], 0.0])
            limit_down = 0.5
        else:
            limit_down = 1.5
        if self.target is not None:
            error = self.target - self.position
            velocity = 1.5 * error
            horizontal = math.hypot(velocity[0], velocity[1])
            if horizontal > 5.0:
                velocity[:2] *= 5.0 / horizontal
            velocity[2] = min(max(velocity[2], -2.5), limit_down)
            self.velocity = velocity
            self.position = self.position + velocity * dt
            self.position[2] = min(self.position[2], 0.0)
        if self.target_yaw is not None:
            error = math.remainder(self.target_yaw - self.attitude[2], 2 * math.pi)
            self.attitude[2] += max(-1.0 * dt, min(1.0 * dt, error))
        if self.mode == COPTER_MODES['LAND'] and self.position[2] > -0.05:
            self.landed_since = t if self.landed_since is None else self.landed_since
            if t - self.landed_since > 1.0:
                self.armed = False
                self.velocity = np.zeros(3)
                self._text(6, 'Disarming motors')
        else:
            self.landed_since = None

    # the loop

    @staticmethod
    def _listen(port: int) -> socket.socket:
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listener.bind(('127.0.0.1', port))
        listener.listen(1)
        listener.setblocking(False)
        return listener

    def _run(self) -> None:
        while not self._stop.is_set():
            with self.lock:
                self._tick(time.monotonic())
            self._stop.wait(0.004)

    def _tick(self, wall: float) -> None:
        if self.listener is None and wall >= self._refuse_until:
            self.listener = self._listen(self.port)
        if self.client is None and self.listener is not None:
            try:
                self.client, _ = self.listener.accept()
                self.client.setblocking(False)
                self.connections += 1
                if not self.booted:
                    self._boot(wall)
            except BlockingIOError:
                pass
        if self.client is None:
            return
        self._read(wall)
        if not self.booted or self.client is None:
            return
        t = self._sim_time(wall)
        dt, self.last_sim = t - self.last_sim, t
        self._boot_events(t)
        self._step_vehicle(t, dt)
        if wall < self._silent_until:
            return
        if int(t) != int(t - dt) or 'heartbeat' not in self.events_done:
            self.events_done.add('heartbeat')
            self._send(self.mav.heartbeat_encode(2, 3, 89 | (128 if self.armed else 0), self.mode,
                                                 4 if self.armed else 3))
        for msg_id, interval in list(self.intervals.items()):
            due = self.next_due.get(msg_id, t)
            if t - due > 5 * interval:
                due = t
            while due <= t:
                self._send_stream(msg_id, t, wall)
                due += interval
            self.next_due[msg_id] = due

    def _boot_events(self, t: float) -> None:
        timeline = [(0.2, 'ready', 'ArduPilot Ready'), (0.4, 'ekf_init', 'EKF3 IMU0 initialised'),
                    (2.0, 'origin', 'EKF3 IMU0 origin set'), (self.ekf_delay, 'gps', 'EKF3 IMU0 is using GPS')]
        for when, key, text in timeline:
            if t >= when and key not in self.events_done:
                self.events_done.add(key)
                self._text(6, text)
        if t >= 0.3 and 'params' not in self.events_done:
            self.events_done.add('params')
            self._send(self.mav.param_value_encode(b'BARO1_GND_PRESS', 94502.8, 9, 1368, 65535))
        if t >= self.rc_mode_switch and 'rc' not in self.events_done:
            self.events_done.add('rc')
            self.mode = COPTER_MODES['STABILIZE']

    def _send_stream(self, msg_id: int, t: float, wall: float) -> None:
        boot_ms = int(t * 1000)
        roll, pitch, yaw = self.attitude
        if msg_id == mavlink.MAVLINK_MSG_ID_ATTITUDE:
            self._send(self.mav.attitude_encode(boot_ms, roll, pitch, yaw, *self.rates))
        elif msg_id == mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED and self._ekf_ready(wall):
            self._send(self.mav.local_position_ned_encode(boot_ms, *self.position, *self.velocity))
        elif msg_id == mavlink.MAVLINK_MSG_ID_HIGHRES_IMU:
            accel = self._body_from_ned(np.array([0.0, 0.0, -GRAVITY]))
            self._send(self.mav.highres_imu_encode(int(t * 1e6), *accel, *self.rates, 0.2, 0.0, 0.4,
                                                   950.0, 0.0, 0.0, 25.0, 0x1FFF))
        elif msg_id == mavlink.MAVLINK_MSG_ID_GLOBAL_POSITION_INT:
            if self._ekf_ready(wall):
                lat = HOME[0] + math.degrees(self.position[0] / 6378137.0)
                lon = HOME[1] + math.degrees(self.position[1] / (6378137.0 * math.cos(math.radians(HOME[0]))))
                fields = (int(lat * 1e7), int(lon * 1e7), int((HOME[2] - self.position[2]) * 1000),
                          int(-self.position[2] * 1000))
            else:
                fields = (0, 0, 0, 0)
            self._send(self.mav.global_position_int_encode(boot_ms, *fields, *(int(v * 100) for v in self.velocity),
                                                           int(math.degrees(yaw) % 360 * 100)))
        elif msg_id == mavlink.MAVLINK_MSG_ID_EKF_STATUS_REPORT:
            flags = 0x033F if self._ekf_ready(wall) else 0x0400
            self._send(self.mav.ekf_status_report_encode(flags, 0.1, 0.1, 0.1, 0.1, 0.0))

    def _body_from_ned(self, vector: np.ndarray) -> np.ndarray:
        roll, pitch, yaw = self.attitude
        cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), \
            math.cos(yaw), math.sin(yaw)
        ned_from_body = np.array([
            [cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy],
            [cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy],
            [-sp, sr * cp, cr * cp]])
        return ned_from_body.T @ vector

    # client messages

    def _read(self, wall: float) -> None:
        try:
            readable, _, _ = select.select([self.client], [], [], 0)
            data = self.client.recv(65536) if readable else None
        except OSError:
            data = b''
        if data == b'':
            self._drop_client()
            return
        for msg in self.parser.parse_buffer(data or b'') or []:
            if msg.get_type() == 'BAD_DATA':
                continue
            self.received.append((wall, msg))
            self._handle(msg, wall)

    def _handle(self, msg, wall: float) -> None:
        kind = msg.get_type()
        if kind == 'COMMAND_LONG':
            result = self._command(msg, wall)
            self._send(self.mav.command_ack_encode(msg.command, result, 0, 0, msg.get_srcSystem(),
                                                   msg.get_srcComponent()))
        elif kind == 'SET_POSITION_TARGET_LOCAL_NED':
            if self.mode == COPTER_MODES['GUIDED'] and self.armed and self.target is not None:
                if not msg.type_mask & 0x7:
                    self.target = np.array([msg.x, msg.y, msg.z])
                if not msg.type_mask & 0x400:
                    self.target_yaw = msg.yaw
        elif kind == 'SET_MODE':
            self._set_mode(msg.custom_mode)

    def _command(self, msg, wall: float) -> int:
        command = msg.command
        if command == 511:
            self.interval_requests.append((wall, int(msg.param1), msg.param2))
            if msg.param2 > 0:
                self.intervals[int(msg.param1)] = msg.param2 * 1e-6
            elif msg.param2 < 0:
                self.intervals.pop(int(msg.param1), None)
            return 0
        if command == 176:
            return 0 if self._set_mode(int(msg.param2)) else 4
        if command == 400:
            if msg.param1 == 1:
                if self.armed:
                    return 0
                if not self._ekf_ready(wall):
                    self._text(2, 'PreArm: Need Position Estimate')
                    return 4
                self.armed = True
                self.pinned = False
                self._text(6, 'Arming motors')
                return 0
            if self.position[2] < -0.1:
                self._text(4, 'Arm: disarm refused while flying')
                return 4
            self.armed = False
            return 0
        if command == 22:
            if not self.armed or self.mode != COPTER_MODES['GUIDED']:
                return 4
            self.target = np.array([self.position[0], self.position[1], -msg.param7])
            return 0
        if command == 21:
            self.mode = COPTER_MODES['LAND']
            return 0
        return 3

    def _set_mode(self, number: int) -> bool:
        if number not in COPTER_MODES.values():
            return False
        self.mode = number
        if number == COPTER_MODES['GUIDED']:
            self.target = self.position.copy() if self.armed and self.position[2] < -0.1 else self.target
        return True

    # bytes out

    def _text(self, severity: int, text: str) -> None:
        self._send(self.mav.statustext_encode(severity, text.encode()))

    def _send(self, msg) -> None:
        self._write(msg.pack(self.mav))

    def _write(self, data: bytes) -> None:
        if self.client is None:
            return
        try:
            self.client.sendall(data)
        except OSError:
            self._drop_client()

    def _drop_client(self) -> None:
        if self.client is not None:
            self.client.close()
            self.client = None
