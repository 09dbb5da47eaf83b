"""The physics side of ArduPilot SITL's JSON interface: a quad X with a tether (no rclpy).

:class:`JsonPhysics` answers SITL's servo packets (:mod:`uav_bridge.json_physics.protocol`): each new
frame holds the four motor PWMs over one time step ``1 / frame_rate``, advances the rotors
(:mod:`uav_bridge.json_physics.quad_motors`) and the UAV rigid body, and returns the JSON state for SITL.
The body is ``tether_dynamics.plant.bodies.body_step`` (the form of Eq. 7.44-7.45: thrust
along body +z, body torque, gravity, the tether's force at the attachment point), the
function the plant and the built-in UAV integrate; the tether's force (N, world) is an input
of :meth:`JsonPhysics.handle`, held over the frame (the caller takes it from the plant after
the previous frame: one frame of explicit delay).

Time step. A frame is ``1 / frame_rate`` of physics time: the rate the packet asks for
(SITL's ``SIM_RATE_HZ``, which SITL walks towards from 1200 Hz by 1 Hz per frame after
start), or a fixed ``frame_rate`` of the configuration, which SITL then adopts (it advances
its clock by the timestamps' change and sets its frame rate from it): with a fixed rate whose
period divides the graph's tick, every tick falls on a frame.

Frames. SITL increments ``frame_count`` only after it parsed a reply, so:

* the count one above the last one answered (or any count first): a new frame, stepped;
* the same count again: SITL resent the frame (after about 1 s without a reply): answered
  with the same reply, not stepped again (no duplicated frame);
* a count more than one above: frames SITL counted that never arrived here, counted as
  lost (it cannot happen while SITL waits for each reply) and stepped once;
* a lower count: SITL restarted. The UAV is put back at rest at its start pose and the
  counting starts again; physics time keeps running (SITL's clock starts from the first
  timestamp it receives, so SITL and the graph keep one time axis).

Ground: below ``start`` height the body rests on its landing gear - height held, level,
still - until the rotors lift it (the vertical speed turns upwards).

Frames of the reply: ENU/FLU inside, NED/FRD at this boundary via :mod:`uav_bridge.frames`;
the NED position is measured from ``origin`` (the world point that is SITL's home, by
default the start position). The specific force is the body's mean acceleration over the
frame minus gravity, so it includes the ground's reaction (level at rest: FRD (0, 0, -g)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field

import numpy as np

from tether_dynamics.plant import bodies
from tether_models.constants import GRAVITY
from uav_bridge import frames
from uav_bridge.json_physics.protocol import PhysicsState
from uav_bridge.json_physics.protocol import ServoPacket
from uav_bridge.json_physics.protocol import format_state
from uav_bridge.json_physics.protocol import parse_servo
from uav_bridge.json_physics.quad_motors import QuadXConfig
from uav_bridge.json_physics.quad_motors import QuadXMotors

NEW, RESEND, GAP, RESTART = 'new', 'resend', 'gap', 'restart'


@dataclass(frozen=True)
class JsonPhysicsConfig:
    """The vehicle, where it starts, and the body's integration step."""

    vehicle: QuadXConfig = field(default_factory=QuadXConfig)
    attach_offset: tuple = (0.0, 0.0, -0.1)     # m, tether attachment from the CoM, body FLU
    start: tuple = (0.0, 0.0, 0.0)              # m, CoM at rest on the ground, world ENU
    heading: float = 0.0                        # rad, start heading, NED (0 = nose north)
    origin: tuple | None = None                 # m, world point of SITL's home; None: start
    gravity: float = GRAVITY                    # m/s^2
    dt: float = 1e-3                            # s, largest body integration step
    start_time: float = 0.0                     # s, physics time before the first frame
    frame_rate: int = 0                         # Hz, physics frames per s; 0: the rate each packet asks for


@dataclass(frozen=True)
class UavFrame:
    """The UAV after a frame, in the graph's frames (ENU world, FLU body)."""

    t: float                                    # s
    position: np.ndarray                        # m, CoM, world
    velocity: np.ndarray                        # m/s, world
    acceleration: np.ndarray                    # m/s^2, mean over the frame, world
    quaternion: np.ndarray                      # (x, y, z, w), body FLU -> world
    angular_velocity: np.ndarray                # rad/s, body FLU
    specific_force: np.ndarray                  # m/s^2, body FLU
    thrusts: np.ndarray                         # N, rotors 1-4
    on_ground: bool


@dataclass
class FrameCounts:
    """What :meth:`JsonPhysics.handle` saw."""

    stepped: int = 0            # frames stepped (new ones, the first after a gap or a restart)
    resent: int = 0             # frames SITL sent again, answered without stepping
    lost: int = 0               # frame counts skipped
    restarts: int = 0           # SITL restarts (frame_count went down)
    rejected: int = 0           # datagrams that are not servo packets


@dataclass(frozen=True)
class Reply:
    """The answer to one datagram: what it was, and the bytes to send back."""

    kind: str                   # NEW, RESEND, GAP or RESTART
    packet: ServoPacket
    data: bytes
    frame: UavFrame             # the UAV after the frame (unchanged by a resend)
    force: np.ndarray           # N, world: the tether's force held over the frame


class JsonPhysics:
    """The quad X answering SITL frame by frame (see the module docstring)."""

    def __init__(self, config: JsonPhysicsConfig) -> None:
        self.config = config
        vehicle = config.vehicle
        self.inertia = np.asarray(vehicle.inertia, dtype=float)
        self.inertia_inv = np.linalg.inv(self.inertia)
        self.rho = np.asarray(config.attach_offset, dtype=float)
        self.start = np.asarray(config.start, dtype=float)
        self.origin = self.start.copy() if config.origin is None else np.asarray(config.origin, dtype=float)
        self.motors = QuadXMotors(vehicle)
        self.body = np.zeros(bodies.BS_SIZE)
        self.counts = FrameCounts()
        self.time_ns = round(config.start_time * 1e9)
        self._last: tuple[int, bytes] | None = None
        self._rest_yaw = math.pi / 2 - config.heading          # ENU yaw of the body's x axis
        self._reset_body()
        self.frame = self._frame(np.zeros(3), on_ground=True)

    @property
    def t(self) -> float:
        """Physics time, s."""
        return self.time_ns * 1e-9

    def _reset_body(self) -> None:
        self.body[:] = 0.0
        self.body[bodies.BS_POS:bodies.BS_POS + 3] = self.start
        self._level(self._rest_yaw)
        self.motors.reset()

    def _level(self, yaw: float) -> None:
        self.body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))

    def handle(self, data: bytes, tether_force) -> Reply:
        """Answer one datagram from SITL under the tether's force (N, world) held over the frame.

        Raises :class:`uav_bridge.json_physics.protocol.SitlJsonError` for a datagram that is not a
        servo packet (counted as rejected).
        """
        try:
            packet = parse_servo(data)
        except ValueError:
            self.counts.rejected += 1
            raise
        count = packet.frame_count
        if self._last is None or count == self._last[0] + 1:
            kind = NEW
        elif count == self._last[0]:
            self.counts.resent += 1
            return Reply(RESEND, packet, self._last[1], self.frame, np.asarray(tether_force, dtype=float))
        elif count > self._last[0]:
            kind = GAP
            self.counts.lost += count - self._last[0] - 1
        else:
            kind = RESTART
            self.counts.restarts += 1
            self._reset_body()
        force = np.asarray(tether_force, dtype=float)
        self._step(packet, force)
        reply = format_state(self.physics_state())
        self._last = (count, reply)
        self.counts.stepped += 1
        return Reply(kind, packet, reply, self.frame, force)

    def _step(self, packet: ServoPacket, force: np.ndarray) -> None:
        frame_ns = round(1e9 / (self.config.frame_rate or packet.frame_rate))
        frame_dt = frame_ns * 1e-9
        n_sub = max(1, math.ceil(frame_dt / self.config.dt - 1e-9))
        dt = frame_dt / n_sub
        v0 = self.body[bodies.BS_VEL:bodies.BS_VEL + 3].copy()
        cfg, vehicle = self.config, self.config.vehicle
        on_ground = False
        steady = self.motors.steady_speed(packet.pwm)
        for _ in range(n_sub):
            self.motors.step(steady, dt)
            thrust, torque = self.motors.wrench_flu()
            bodies.body_step(self.body, vehicle.mass, self.inertia, self.inertia_inv, self.rho, thrust, torque,
                             force, cfg.gravity, dt)
            on_ground = self._ground()
        self.time_ns += frame_ns
        acceleration = (self.body[bodies.BS_VEL:bodies.BS_VEL + 3] - v0) / frame_dt
        self.frame = self._frame(acceleration, on_ground)

    def _ground(self) -> bool:
        """Hold the body on its landing gear while it presses down on the ground."""
        b = self.body
        if b[bodies.BS_POS + 2] > self.start[2]:
            return False
        b[bodies.BS_POS + 2] = self.start[2]
        if b[bodies.BS_VEL + 2] > 0.0:
            return False
        x, y, z, w = b[bodies.BS_QUAT:bodies.BS_QUAT + 4]
        self._level(math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)))
        b[bodies.BS_VEL:bodies.BS_VEL + 3] = 0.0
        b[bodies.BS_OMEGA:bodies.BS_OMEGA + 3] = 0.0
        return True

    def _frame(self, acceleration: np.ndarray, on_ground: bool) -> UavFrame:
        b = self.body
        quaternion = b[bodies.BS_QUAT:bodies.BS_QUAT + 4].copy()
        specific = np.empty(3)
        bodies.quat_rotate_inverse(quaternion, acceleration + [0.0, 0.0, self.config.gravity], specific)
        return UavFrame(self.t, b[0:3].copy(), b[3:6].copy(), acceleration, quaternion, b[10:13].copy(), specific,
                        self.motors.thrusts(), on_ground)

    def physics_state(self) -> PhysicsState:
        """The current frame in SITL's conventions."""
        f = self.frame
        quaternion = frames.quaternion_enu_to_ned(f.quaternion)
        return PhysicsState(timestamp=f.t, gyro=frames.flu_to_frd(f.angular_velocity),
                            accel_body=frames.flu_to_frd(f.specific_force),
                            position=frames.enu_to_ned(f.position - self.origin),
                            velocity=frames.enu_to_ned(f.velocity), attitude=np.array(frames.quaternion_to_euler(*quaternion)),
                            quaternion=np.array(quaternion))
