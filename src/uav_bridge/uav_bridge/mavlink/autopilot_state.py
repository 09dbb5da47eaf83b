"""What the bridge knows of the autopilot at the other end of the link (no rclpy, no I/O).

:class:`AutopilotState` is fed every received MAVLink message with the wall time of its
arrival and answers: is the link up, is the data stale, is the autopilot armed and in which
mode, is its position estimate ready, what is the link waiting for, and did the autopilot
reboot. Events returned by :meth:`AutopilotState.on_message` tell the session when to
request the telemetry streams again:

* ``link_up``: the first HEARTBEAT on a new connection;
* ``resumed``: a HEARTBEAT after a gap longer than ``link_timeout`` (the autopilot may
  have restarted behind a link that stayed open, e.g. UDP);
* ``reboot``: the autopilot's time since boot went backwards by more than
  ``reboot_tolerance`` (a restarted autopilot forgets the requested message intervals).

ArduPilot's behaviour these rules follow is in ``../shared/notes/ardupilot-sitl-mavlink.md``:
LOCAL_POSITION_NED only once the EKF uses GPS, arming refused with STATUSTEXT reasons before.
"""

from __future__ import annotations

import collections

from pymavlink import mavutil

MAV_TYPE_GCS = 6
MAV_AUTOPILOT_INVALID = 8
MAV_MODE_FLAG_SAFETY_ARMED = 128
EKF_POSITION_FLAGS = 0x0001 | 0x0002 | 0x0008 | 0x0010 | 0x0020
"""EKF_STATUS_REPORT flags of a usable position estimate: attitude, horizontal velocity,
absolute horizontal position, absolute vertical position (ESTIMATOR_STATUS_FLAGS)."""
EKF_CONST_POS_MODE = 0x0080
"""The EKF holds a constant position (no GPS): flag of an estimate not ready for GUIDED."""

MAV_SEVERITY_WARNING = 4

BOOT_TIME_USEC_MESSAGES = frozenset({'HIGHRES_IMU', 'RAW_IMU'})
"""Messages whose ``time_usec`` is ArduPilot's time since boot (GPS_RAW_INT's is UNIX time)."""


def boot_time(msg) -> float | None:
    """Return the autopilot's time since boot (s) a message carries, or None."""
    value = getattr(msg, 'time_boot_ms', None)
    if value is not None:
        return value * 1e-3
    if msg.get_type() in BOOT_TIME_USEC_MESSAGES:
        return msg.time_usec * 1e-6
    return None


class AutopilotState:
    """Link, flight and estimator state of one autopilot, updated message by message.

    Times are the receiver's wall clock (s, monotonic): staleness is about the link, which
    runs in wall time whatever the autopilot's simulation speed.
    """

    def __init__(self, link_timeout: float = 3.0, statustext_lines: int = 10,
                 reboot_tolerance: float = 1.0, own_system: int = 255) -> None:
        self.link_timeout = link_timeout
        self.reboot_tolerance = reboot_tolerance
        self.own_system = own_system
        self.system_id: int | None = None
        self.component_id: int | None = None
        self.mav_type: int | None = None
        self.connected = False
        self.armed = False
        self.mode = ''
        self.custom_mode: int | None = None
        self.ekf_flags = 0
        self.boot_time: float | None = None
        self.last_heartbeat: float | None = None
        self.last_local_position: float | None = None
        self.last_seen: dict[str, float] = {}
        self.status_lines: collections.deque[tuple[int, str]] = collections.deque(maxlen=statustext_lines)
        self.status_serial = 0
        self.reconnects = 0
        self.reboots = 0
        self.bad_packets = 0
        self._heard_on_connection = False

    # link events

    def connection_made(self) -> None:
        """A transport to the autopilot was opened: stale, and neither armed nor in a mode, until its first HEARTBEAT
        (the autopilot behind a new connection may have restarted).
        """
        self.connected = True
        self.reconnects += 1
        self._heard_on_connection = False
        self.last_heartbeat = None
        self._forget_flight()

    def connection_lost(self) -> None:
        """The transport closed: everything is stale, neither armed nor in a mode, until the autopilot is heard again."""
        self.connected = False
        self.last_local_position = None
        self._forget_flight()

    def _forget_flight(self) -> None:
        """Armed and mode are no longer known (a closed link, a new one, a reboot): cleared until the next HEARTBEAT."""
        self.armed = False
        self.mode = ''
        self.custom_mode = None

    def on_bad_data(self, count: int = 1) -> None:
        """Count bytes or packets that were not valid MAVLink."""
        self.bad_packets += count

    # messages

    def accepts(self, msg) -> bool:
        """True for messages of the autopilot (the first vehicle that sent a HEARTBEAT)."""
        source = msg.get_srcSystem()
        if source == self.own_system:
            return False
        if self.system_id is None:
            return msg.get_type() != 'HEARTBEAT' or self._is_vehicle(msg)
        return source == self.system_id

    def on_message(self, msg, now: float) -> list[str]:
        """Update with ``msg`` received at wall time ``now``; return the events it caused."""
        if not self.accepts(msg):
            return []
        events = []
        kind = msg.get_type()
        self.last_seen[kind] = now
        if kind == 'HEARTBEAT':
            events += self._on_heartbeat(msg, now)
        elif kind == 'STATUSTEXT':
            self.status_lines.append((msg.severity, msg.text))
            self.status_serial += 1
        elif kind == 'EKF_STATUS_REPORT':
            self.ekf_flags = msg.flags
        elif kind == 'LOCAL_POSITION_NED':
            self.last_local_position = now
        seconds = boot_time(msg)
        if seconds is not None and self.system_id is not None:
            if self.boot_time is not None and seconds < self.boot_time - self.reboot_tolerance:
                self.reboots += 1
                self.ekf_flags = 0
                self.last_local_position = None
                self.last_seen = {kind: now}
                self._forget_flight()
                events.append('reboot')
            self.boot_time = seconds
        return events

    def _is_vehicle(self, msg) -> bool:
        return msg.type != MAV_TYPE_GCS and msg.autopilot != MAV_AUTOPILOT_INVALID

    def _on_heartbeat(self, msg, now: float) -> list[str]:
        if not self._is_vehicle(msg):
            return []
        events = []
        if self.system_id is None:
            self.system_id = msg.get_srcSystem()
            self.component_id = msg.get_srcComponent()
        if not self._heard_on_connection:
            self._heard_on_connection = True
            events.append('link_up')
        elif self.last_heartbeat is not None and now - self.last_heartbeat > self.link_timeout:
            events.append('resumed')
        self.last_heartbeat = now
        self.mav_type = msg.type
        self.armed = bool(msg.base_mode & MAV_MODE_FLAG_SAFETY_ARMED)
        self.custom_mode = msg.custom_mode
        self.mode = mavutil.mode_string_v10(msg)
        return events

    # answers

    @property
    def status_text(self) -> list[str]:
        """The latest STATUSTEXT lines, oldest first."""
        return [text for _, text in self.status_lines]

    def warnings_since(self, serial: int) -> list[str]:
        """STATUSTEXT lines of severity WARNING or worse received after line number ``serial``."""
        count = min(self.status_serial - serial, len(self.status_lines))
        recent = list(self.status_lines)[len(self.status_lines) - count:] if count > 0 else []
        return [text for severity, text in recent if severity <= MAV_SEVERITY_WARNING]

    def heartbeat_age(self, now: float) -> float:
        """Seconds since the last HEARTBEAT, -1 before the first one."""
        return -1.0 if self.last_heartbeat is None else now - self.last_heartbeat

    def stale(self, now: float) -> bool:
        """True when the link is closed or no HEARTBEAT came for longer than ``link_timeout``."""
        return (not self.connected or self.last_heartbeat is None
                or now - self.last_heartbeat > self.link_timeout)

    def position_ready(self, now: float) -> bool:
        """True while LOCAL_POSITION_NED arrives (ArduPilot sends it only once the EKF uses GPS)."""
        return (not self.stale(now) and self.last_local_position is not None
                and now - self.last_local_position <= self.link_timeout)

    def mode_number(self, name: str) -> int | None:
        """The custom_mode number of a flight mode name for this vehicle type, or None."""
        mapping = mavutil.mode_mapping_byname(self.mav_type) if self.mav_type is not None else None
        return None if mapping is None else mapping.get(name.upper())

    def mode_names(self) -> list[str]:
        """The flight mode names this vehicle type knows."""
        mapping = mavutil.mode_mapping_byname(self.mav_type) if self.mav_type is not None else None
        return sorted(mapping) if mapping else []

    def waiting_for(self, now: float, url: str, missing_streams: list[str]) -> str:
        """Say what the link waits for; empty once the position estimate streams in."""
        if not self.connected:
            return f'connection to {url}'
        if self.last_heartbeat is None or not self._heard_on_connection:
            return f'first HEARTBEAT on {url}'
        if self.stale(now):
            return f'HEARTBEAT (none for {now - self.last_heartbeat:.1f} s)'
        if not self.position_ready(now):
            reason = 'position estimate: no LOCAL_POSITION_NED yet (the EKF is not using GPS)'
            if self.ekf_flags:
                reason += f', EKF flags 0x{self.ekf_flags:04x}'
            return reason
        if missing_streams:
            return 'telemetry streams: ' + ', '.join(missing_streams)
        return ''
