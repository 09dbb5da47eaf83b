"""A test double of ArduPilot SITL's side of the JSON physics protocol (UDP).

It behaves as the note (ardupilot-sitl-mavlink.md) and ArduPilot's JSON backend documentation
describe SITL: a servo packet per frame (16 or 32 channels, magic 18458 / 29569, frame_rate,
frame_count) to the physics port; it waits for the reply and, when none comes within
``resend_after`` s, sends the same packet again (same frame_count). Replies are parsed the way
SITL parses them: newlines become string ends, the text between the last two is used (so a
reply needs a newline before and after it), each key is found by substring search (section
first, then the key after it) and its value read two characters after the key (quote and
colon), vectors with ``sscanf("[%f, %f, %f]")`` rules. frame_count goes up only when a reply
parsed with all required fields; SITL's clock advances by the change of ``timestamp`` (a
backwards step is a reset). :meth:`restart` is a SITL restart: a new socket, frame_count 0.
"""

from __future__ import annotations

import re
import select
import socket
from dataclasses import dataclass
from dataclasses import field

import numpy as np

from uav_bridge.json_physics.protocol import ServoPacket
from uav_bridge.json_physics.protocol import encode_servo

_NUMBER = r'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf)'
_FLOAT = re.compile(r'\s*(' + _NUMBER + ')')
_VECTOR3 = re.compile(r'\[\s*(' + _NUMBER + r'),\s*(' + _NUMBER + r'),\s*(' + _NUMBER + ')')
_VECTOR4 = re.compile(r'\[\s*(' + _NUMBER + r'),\s*(' + _NUMBER + r'),\s*(' + _NUMBER + r'),\s*(' + _NUMBER + ')')

# (section, key, kind, required) in SITL's key table order.
KEY_TABLE = (('', 'timestamp', 'double', True), ('imu', 'gyro', 'vector3', True),
             ('imu', 'accel_body', 'vector3', True), ('', 'position', 'vector3', True),
             ('', 'quaternion', 'quaternion', False), ('', 'attitude', 'vector3', False),
             ('', 'velocity', 'vector3', True))


def parse_sensors(text: str) -> dict | None:
    """SITL's reading of one reply line: the fields found, or None when a required one is missing."""
    found: dict = {}
    for section, key, kind, required in KEY_TABLE:
        start = text.find(section)
        if start < 0:
            if required:
                return None
            continue
        at = text.find(key, start + len(section) + 1)
        if at < 0:
            if required:
                return None
            continue
        value = text[at + len(key) + 2:]
        if kind == 'double':
            match = _FLOAT.match(value)
            found[key] = float(match.group(1)) if match else 0.0
            continue
        match = (_VECTOR4 if kind == 'quaternion' else _VECTOR3).match(value)
        if match is None:               # SITL stops parsing here, the reply's later fields are lost
            return None
        found[key] = np.array([float(g) for g in match.groups()])
    if 'quaternion' not in found and 'attitude' not in found:
        return None
    return found


@dataclass
class PeerLog:
    """What the peer did."""

    sent: int = 0                   # datagrams sent (frames and resends)
    resends: int = 0                # packets sent again after a silence
    parsed: list = field(default_factory=list)      # the parsed replies, in order
    unparsed: int = 0               # replies SITL's parser would drop
    clock: float = 0.0              # SITL's clock, s (the sum of timestamp changes)
    repeated: int = 0               # replies with the previous reply's timestamp (SITL counts them as frames)
    resets: int = 0                 # timestamps that went backwards


class SitlJsonPeerDouble:
    """SITL's side of the JSON interface, driven step by step by a test."""

    def __init__(self, port: int, frame_rate: int = 400, channels: int = 16, resend_after: float = 0.2) -> None:
        self.address = ('127.0.0.1', port)
        self.frame_rate = frame_rate
        self.channels = channels
        self.resend_after = resend_after
        self.log = PeerLog()
        self.pwm = [1000] * channels
        self._open()

    def _open(self) -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(('127.0.0.1', 0))
        self.frame_count = 0
        self.last_timestamp = 0.0
        self.buffer = b''

    def close(self) -> None:
        """Close the socket."""
        self.sock.close()

    def restart(self) -> None:
        """A SITL restart: new socket (new port), frame_count from 0, timestamps from 0."""
        self.sock.close()
        self._open()

    def packet(self) -> bytes:
        """The servo packet of the current frame."""
        return encode_servo(ServoPacket(self.frame_rate, self.frame_count, tuple(self.pwm)))

    def send(self) -> None:
        """Send the current frame's packet (again, if it was sent before)."""
        self.sock.sendto(self.packet(), self.address)
        self.log.sent += 1

    def receive(self, timeout: float | None = None) -> dict | None:
        """Wait for a reply and parse it as SITL does; the fields, or None (silence or unparsed)."""
        readable, _, _ = select.select([self.sock], [], [], self.resend_after if timeout is None else timeout)
        if not readable:
            return None
        data, _ = self.sock.recvfrom(4096)
        self.buffer += data.replace(b'\n', b'\0')
        end = self.buffer.rfind(b'\0')
        if end <= 0:
            return None
        begin = self.buffer.rfind(b'\0', 0, end)
        if begin < 0:
            return None
        fields = parse_sensors(self.buffer[begin + 1:end].decode('ascii', errors='replace'))
        self.buffer = self.buffer[end:]
        if fields is None:
            self.log.unparsed += 1
            return None
        timestamp = fields['timestamp']
        if timestamp == self.last_timestamp and self.frame_count:
            self.log.repeated += 1
        if timestamp < self.last_timestamp:
            self.log.resets += 1
        else:
            self.log.clock += timestamp - self.last_timestamp
        self.last_timestamp = timestamp
        self.frame_count += 1
        self.log.parsed.append(fields)
        return fields

    def frame(self, serve, resends: int = 3) -> dict:
        """One frame: send, let ``serve()`` answer, receive; resend after a silence, as SITL."""
        self.send()
        serve()
        for _ in range(resends + 1):
            fields = self.receive()
            if fields is not None:
                return fields
            self.log.resends += 1
            self.send()
            serve()
        raise AssertionError(f'no reply to frame {self.frame_count} after {resends} resends')
