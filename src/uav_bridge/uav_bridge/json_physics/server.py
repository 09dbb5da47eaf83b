"""The JSON physics server: SITL's servo packets in over UDP, the tethered quad X's state out (no rclpy).

:class:`JsonPhysicsServer` binds the physics side's UDP port (9002 + 10 per SITL instance) and
answers every servo packet with :class:`uav_bridge.json_physics.model.JsonPhysics`, replying to the
sender's address. SITL waits for each reply before it runs on, so SITL is in lockstep with
this server and the physics time is the one clock of the run.

Datagrams already queued when one is read are read too; each is handled in order (new frames
stepped, resends answered from the cache) and only the last one is answered. SITL takes
any reply as the answer to the packet it is waiting for, so an extra reply in its socket
leaves it one frame behind for the rest of the run: resends that piled up during a silence
must get one answer, and when a resend raced a late reply (SITL then consumed the copy as
the next frame's answer and sent two frames without waiting), the two frames arrive
together and the single answer to the newer one puts SITL back in step. SITL's clock is
unaffected either way (a repeated reply carries the same timestamp).

The tether's force comes from a :class:`PlantTether` (the plant in the same process, stepped
with the UAV's pose every ``period`` of physics time; its force acts from then on) or a
:class:`HeldForce` the caller sets (the node: the plant node's wrench).
"""

from __future__ import annotations

import copy
import select
import socket
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tether_dynamics.plant import PlantInputs
from tether_dynamics.plant import PlantOutputs
from tether_dynamics.plant import TetherPlant
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import Reply
from uav_bridge.json_physics.model import UavFrame
from uav_bridge.json_physics.protocol import ServoPacket
from uav_bridge.json_physics.protocol import SitlJsonError
from uav_bridge.json_physics.protocol import encode_servo

MAX_DATAGRAM = 2048


@dataclass(frozen=True)
class PlatformPose:
    """The platform (boat frame) in world at one time."""

    position: np.ndarray
    quaternion: np.ndarray                  # (x, y, z, w), boat -> world
    velocity: np.ndarray
    angular_velocity: np.ndarray            # world


def resting_platform(position=(0.0, 0.0, 0.0)) -> Callable[[float], PlatformPose]:
    """A platform standing still at ``position`` (world), level."""
    pose = PlatformPose(np.asarray(position, dtype=float), np.array([0.0, 0.0, 0.0, 1.0]), np.zeros(3), np.zeros(3))
    return lambda t: pose


def heaving_platform(amplitude: float, period: float, position=(0.0, 0.0, 0.0)) -> Callable[[float], PlatformPose]:
    """A level platform heaving sinusoidally: ``amplitude`` m, ``period`` s, about ``position`` (world)."""
    centre = np.asarray(position, dtype=float)
    omega = 2.0 * np.pi / period

    def pose(t: float) -> PlatformPose:
        heave = np.array([0.0, 0.0, amplitude * np.sin(omega * t)])
        rate = np.array([0.0, 0.0, amplitude * omega * np.cos(omega * t)])
        return PlatformPose(centre + heave, np.array([0.0, 0.0, 0.0, 1.0]), rate, np.zeros(3))
    return pose


class StraightTether:
    """ArduPilot's SIM_Tether model, the baseline: a straight line from the guide way to the UAV.

    The force on the UAV points along the line towards the guide way, with the magnitude of the
    whole line's weight mu |d| g, plus a spring-damper (``spring`` N/m, ``damping`` N s/m)
    on the stretch beyond ``max_length``: no sag, no reel, no dynamics of the line (the model
    of libraries/SITL/SIM_Tether.cpp, there with mu = 0.0167 kg/m, 100 N/m, 10 N s/m). Stepped
    like :class:`PlantTether`, every ``period`` s with the UAV's centre of mass.
    """

    def __init__(self, platform: Callable[[float], PlatformPose], guide_way_offset, linear_density: float,
                 max_length: float, gravity: float, period: float, spring: float = 100.0,
                 damping: float = 10.0) -> None:
        self.platform = platform
        self.offset = np.asarray(guide_way_offset, dtype=float)
        self.mu, self.max_length, self.gravity = linear_density, max_length, gravity
        self.spring, self.damping = spring, damping
        self.period_ns = round(period * 1e9)
        self.next_ns: int | None = None
        self.value = np.zeros(3)
        self._stretch: tuple[float, float] | None = None      # (t, stretch) of the last step

    def force(self) -> np.ndarray:
        """The line's force on the UAV (N, world) from the last step."""
        return self.value

    def update(self, frame: UavFrame) -> None:
        """Recompute the force when the frame reached the next step time."""
        t_ns = round(frame.t * 1e9)
        if self.next_ns is not None and t_ns < self.next_ns:
            return
        self.next_ns = (t_ns // self.period_ns + 1) * self.period_ns
        p = self.platform(frame.t)
        anchor = p.position + self.offset
        line = anchor - frame.position
        length = float(np.linalg.norm(line))
        direction = line / length if length > 0.0 else np.zeros(3)
        magnitude = self.mu * length * self.gravity
        stretch = max(length - self.max_length, 0.0)
        if stretch > 0.0:
            rate = 0.0 if self._stretch is None or frame.t <= self._stretch[0] else \
                (stretch - self._stretch[1]) / (frame.t - self._stretch[0])
            magnitude += self.spring * stretch + self.damping * rate
        self._stretch = (frame.t, stretch)
        self.value = direction * magnitude


class PlantTether:
    """The plant's force on the UAV, the plant stepped every ``period`` s with the UAV prescribed."""

    def __init__(self, plant: TetherPlant, platform: Callable[[float], PlatformPose], period: float) -> None:
        if plant.config.uav.mode != 'prescribed':
            raise ValueError('the JSON physics server integrates the UAV: the plant needs uav.mode prescribed')
        self.plant = plant
        self.platform = platform
        self.period_ns = round(period * 1e9)
        self.next_ns: int | None = None
        self.outputs: PlantOutputs | None = None

    def force(self) -> np.ndarray:
        """The tether's force on the UAV (N, world) from the last plant step; none before it."""
        return np.zeros(3) if self.outputs is None else self.outputs.force_on_uav

    def update(self, frame: UavFrame) -> PlantOutputs | None:
        """Step the plant when the frame reached its next step time; the outputs of a step, else None."""
        t_ns = round(frame.t * 1e9)
        if self.next_ns is not None and t_ns < self.next_ns:
            return None
        self.next_ns = (t_ns // self.period_ns + 1) * self.period_ns
        p = self.platform(frame.t)
        self.outputs = self.plant.step(frame.t, PlantInputs(
            platform_position=p.position, platform_quaternion=p.quaternion, platform_velocity=p.velocity,
            platform_angular_velocity=p.angular_velocity, uav_position=frame.position,
            uav_quaternion=frame.quaternion, uav_velocity=frame.velocity,
            uav_angular_velocity=frame.angular_velocity))
        return self.outputs


class HeldForce:
    """A tether force set by the caller (the node: the plant's latest wrench), held until set again."""

    def __init__(self) -> None:
        self.value = np.zeros(3)

    def force(self) -> np.ndarray:
        """The force on the UAV, N, world."""
        return self.value

    def update(self, frame: UavFrame) -> None:
        """Nothing to step: the caller sets :attr:`value`."""


class JsonPhysicsServer:
    """UDP loop around :class:`JsonPhysics` (see the module docstring)."""

    def __init__(self, physics: JsonPhysics, port: int, host: str = '127.0.0.1',
                 tether: PlantTether | StraightTether | HeldForce | None = None, log: Callable[[str], None] = print) -> None:
        self.physics = physics
        self.tether = tether
        self.log = log
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind((host, port))
        self.port = self.sock.getsockname()[1]
        self.peer: tuple | None = None

    def close(self) -> None:
        """Release the port."""
        self.sock.close()

    def warm_up(self) -> None:
        """Answer a made-up frame with scratch copies of the physics and the tether, so that numba
        compiles their kernels now (seconds in a fresh checkout) and not inside the reply to SITL's
        first frame. A compile there holds the reply over SITL's 1 s resend period: copies of frame 0
        pile up, and how SITL's start then goes depends on the wall clock (two flights at once at
        100x and 1x took two different tracks, 18.8 mm apart, in fresh checkouts only).
        """
        scratch = copy.deepcopy(self.physics)
        scratch.handle(encode_servo(ServoPacket(800, 0, (1500,) * 16)), np.zeros(3))
        if self.tether is not None:
            copy.deepcopy(self.tether).update(scratch.frame)

    def waiting(self, timeout: float) -> bool:
        """Whether a servo packet is queued within ``timeout`` s (left unread): SITL sent its next frame and waits.

        Once the reply to the last frame of a tick is out, SITL runs that frame's loop (reading
        its MAVLink ports among the rest) and sends the next packet: MAVLink bytes written after
        this returned True reach SITL's first loop after the next reply, whatever the pace.
        """
        readable, _, _ = select.select([self.sock], [], [], timeout)
        return bool(readable)

    def poll(self, timeout: float) -> list[Reply]:
        """Wait up to ``timeout`` s for servo packets and answer them; every datagram's reply, in order
        (only the last one is sent).
        """
        readable, _, _ = select.select([self.sock], [], [], timeout)
        if not readable:
            return []
        datagrams = []
        while True:
            try:
                datagrams.append(self.sock.recvfrom(MAX_DATAGRAM, socket.MSG_DONTWAIT))
            except BlockingIOError:
                break
        answered = [(reply, address) for data, address in datagrams
                     if (reply := self._answer(data, address)) is not None]
        if not answered:
            return []
        reply, address = answered[-1]
        self.sock.sendto(reply.data, address)
        return [reply for reply, _ in answered]

    def _answer(self, data: bytes, address: tuple) -> Reply | None:
        force = self.tether.force() if self.tether is not None else np.zeros(3)
        try:
            reply = self.physics.handle(data, force)
        except SitlJsonError as error:
            self.log(f'ignored a datagram from {address[0]}:{address[1]}: {error}')
            return None
        if address != self.peer:
            self.log(f'SITL at {address[0]}:{address[1]} (frame {reply.packet.frame_count}, '
                     f'{reply.packet.frame_rate} Hz, {len(reply.packet.pwm)} channels)')
            self.peer = address
        if reply.kind == 'restart':
            self.log(f'SITL restarted (frame_count {reply.packet.frame_count}): the UAV is back at its start')
        elif reply.kind == 'gap':
            self.log(f'frame_count jumped to {reply.packet.frame_count}: {self.physics.counts.lost} frames lost')
        if reply.kind != 'resend' and self.tether is not None:
            self.tether.update(self.physics.frame)
        return reply

