"""ArduPilot SITL's JSON physics protocol, the physics side of it (no rclpy).

With ``--model JSON:<ip>`` ArduPilot SITL sends, each physics frame, a binary servo packet
by UDP to port 9002 (+10 per instance) of the physics program, and waits for one reply to the
sender's address. The packet is little-endian ``<HHI16H`` (40 bytes, magic 18458) or, with
``SERVO_32_ENABLE = 1``, ``<HHI32H`` (72 bytes, magic 29569): magic, frame_rate (Hz: the time
step SITL asks for), frame_count (incremented only after SITL parsed a reply, so a resend
carries the same count; 0 again after a SITL restart), and the PWM of each channel in µs.

The reply is one line of JSON, preceded and terminated by a newline: SITL turns newlines into
string ends and parses the text between the last two. Its parser finds each key by substring
search and then skips two characters (the closing quote and the colon), so a key is written
``"key":value`` with no blank before or after the colon, and vectors as ``[a,b,c]``. The
fields (MAVLink conventions, FRD body and NED earth frame):

* ``timestamp`` (s) - physics time; SITL advances its clock by its change (a backwards step
  is a physics reset);
* ``imu.gyro`` (rad/s, body FRD) and ``imu.accel_body`` (specific force, m/s², body FRD:
  level at rest it reads ``[0,0,-9.81]``);
* ``position`` (m, NED from SITL's home) and ``velocity`` (m/s, NED);
* ``attitude`` (roll, pitch, yaw of body FRD in NED, rad) and ``quaternion`` (w, x, y, z,
  body FRD -> NED); SITL uses the quaternion when both are present.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np

MAGIC_16 = 18458
MAGIC_32 = 29569
FORMAT_16 = struct.Struct('<HHI16H')
FORMAT_32 = struct.Struct('<HHI32H')
PORT = 9002
"""UDP port of the physics side for SITL instance 0 (+10 per instance)."""


class SitlJsonError(ValueError):
    """A datagram that is not a SITL servo packet; the message says why."""


@dataclass(frozen=True)
class ServoPacket:
    """One servo packet: the frame SITL asks for and its channel outputs."""

    frame_rate: int                 # Hz
    frame_count: int
    pwm: tuple[int, ...]            # µs, 16 or 32 channels


def physics_port(instance: int) -> int:
    """The UDP port SITL instance ``instance`` sends its servo packets to."""
    return PORT + 10 * instance


def parse_servo(data: bytes) -> ServoPacket:
    """Decode a servo packet (16- or 32-channel form); SitlJsonError for anything else."""
    if len(data) < 2:
        raise SitlJsonError(f'servo packet of {len(data)} bytes: too short for a magic number')
    magic = int.from_bytes(data[:2], 'little')
    layout = {MAGIC_16: FORMAT_16, MAGIC_32: FORMAT_32}.get(magic)
    if layout is None:
        raise SitlJsonError(f'servo packet magic {magic}: expected {MAGIC_16} (16 channels) or {MAGIC_32} (32)')
    if len(data) != layout.size:
        raise SitlJsonError(f'servo packet with magic {magic} has {len(data)} bytes, expected {layout.size}')
    fields = layout.unpack(data)
    if fields[1] == 0:
        raise SitlJsonError('servo packet with frame_rate 0')
    return ServoPacket(frame_rate=fields[1], frame_count=fields[2], pwm=tuple(fields[3:]))


def encode_servo(packet: ServoPacket) -> bytes:
    """Encode a servo packet (the SITL side; the tests' peer sends these)."""
    layout, magic = (FORMAT_16, MAGIC_16) if len(packet.pwm) == 16 else (FORMAT_32, MAGIC_32)
    if len(packet.pwm) not in (16, 32):
        raise SitlJsonError(f'a servo packet carries 16 or 32 channels, got {len(packet.pwm)}')
    return layout.pack(magic, packet.frame_rate, packet.frame_count, *packet.pwm)


@dataclass(frozen=True)
class PhysicsState:
    """What the reply carries, in MAVLink's frames (NED earth, FRD body)."""

    timestamp: float                # s
    gyro: np.ndarray                # rad/s, body FRD
    accel_body: np.ndarray          # m/s^2, specific force, body FRD
    position: np.ndarray            # m, NED from home
    velocity: np.ndarray            # m/s, NED
    attitude: np.ndarray            # rad, roll, pitch, yaw (Z-Y-X of body FRD in NED)
    quaternion: np.ndarray          # w, x, y, z, body FRD -> NED


def _vector(values) -> str:
    return '[' + ','.join(repr(float(v)) for v in values) + ']'


def format_state(state: PhysicsState) -> bytes:
    """The reply datagram: newline, one JSON object written for SITL's parser, newline."""
    text = (f'{{"timestamp":{float(state.timestamp)!r},'
            f'"imu":{{"gyro":{_vector(state.gyro)},"accel_body":{_vector(state.accel_body)}}},'
            f'"position":{_vector(state.position)},"velocity":{_vector(state.velocity)},'
            f'"attitude":{_vector(state.attitude)},"quaternion":{_vector(state.quaternion)}}}')
    return ('\n' + text + '\n').encode('ascii')
