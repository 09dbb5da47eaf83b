"""The built-in UAV: the plant's UAV rigid body flown by the station controller (no rclpy).

For runs without an autopilot. The body is ``tether_dynamics.plant.bodies.body_step`` (the
form of Eq. 7.44-7.45: thrust along body +z, body torque, gravity, the tether's force at the
attachment point), the same function the plant integrates; the controller is
:class:`uav_bridge.multirotor_control.StationController`. :class:`BuiltinUav` answers the
commands the MAVLink bridge forwards to ArduPilot, with ArduCopter's meaning: GUIDED and
LAND modes, arm, take off to an altitude above the take-off point, position targets in
GUIDED, LAND descending at ``land_speed`` and disarming on the ground. The ground is level at
the height of ``start``; stepped with a ``pad`` (where the CoM rests on a landing pad on the
boat, moving with the deck), within ``pad_radius`` of it horizontally the ground is the pad.
While disarmed the body rests on the ground: at ``start`` before the first flight (on the
pad if ``start`` is over it), where it touched down after a landing, riding with the pad if
it touched down on it. With a
``start_height`` it starts armed in GUIDED, hovering that high above ``start``, as a
tethered run starts with the tether already deployed to the UAV in the air. Its estimate
is ready at once (it has no EKF start-up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tether_common.rotation import quaternion_rotation
from tether_dynamics.plant import bodies
from tether_dynamics.plant.ends import cross
from uav_bridge.multirotor_control import StationController
from uav_bridge.multirotor_control import UavBodyState

MODES = ('GUIDED', 'LAND')


@dataclass(frozen=True)
class BuiltinUavConfig:
    """The body, where it starts, and how it lands."""

    mass: float = 2.0                                   # kg
    inertia: tuple = ((0.03, 0.0, 0.0), (0.0, 0.03, 0.0), (0.0, 0.0, 0.05))   # kg m^2, body
    attach_offset: tuple = (0.0, 0.0, -0.1)             # m, tether attachment from the CoM, body FLU
    start: tuple = (0.0, 0.0, 0.0)                      # m, CoM at rest on the ground, world
    start_height: float = 0.0                           # m above start hovering at t = 0 (armed, GUIDED); 0: landed
    gravity: float = 9.80665                            # m/s^2
    dt: float = 1e-3                                    # s, body integration step
    land_speed: float = 0.5                             # m/s, LAND descent rate
    landed_below: float = 0.05                          # m above the start height counts as landed
    pad_radius: float = 1.0                             # m, horizontal extent of the landing pad around its centre


@dataclass(frozen=True)
class BuiltinUavState:
    """What the built-in UAV reports after a step (the topics the bridge publishes)."""

    armed: bool
    mode: str
    position: np.ndarray            # m, world
    velocity: np.ndarray            # m/s, world
    acceleration: np.ndarray        # m/s^2, world
    quaternion: np.ndarray          # (x, y, z, w), body FLU -> world
    angular_velocity: np.ndarray    # rad/s, body


class BuiltinUav:
    """Body plus controller plus command logic, stepped with explicit time."""

    def __init__(self, config: BuiltinUavConfig) -> None:
        self.config = config
        self.inertia = np.asarray(config.inertia, dtype=float)
        self.inertia_inv = np.linalg.inv(self.inertia)
        self.rho = np.asarray(config.attach_offset, dtype=float)
        self.start = np.asarray(config.start, dtype=float)
        self.ground = self.start.copy()
        self._pad: np.ndarray | None = None       # m, world: the pad's rest point at the last step
        self._riding = False                      # at rest on the pad, moving with it
        self._on_pad = np.zeros(3)                # m, world: where the UAV rests relative to the pad's rest point
        self._ground_z = float(self.start[2])
        self.body = np.zeros(bodies.BS_SIZE)
        self.armed = False
        self.mode = 'GUIDED'
        self.reference = self.start.copy()
        self.yaw = math.pi / 2
        self.thrust = 0.0
        self.torque = np.zeros(3)
        self._rest()
        self.controller = StationController(config.mass, self.inertia, config.gravity)
        self._t: float | None = None
        if config.start_height > 0.0:
            self.body[bodies.BS_POS + 2] += config.start_height
            self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3].copy()
            self.armed = True

    def warm_up(self) -> None:
        """Advance a scratch copy of the body one step, so that numba compiles ``body_step`` now
        (seconds in a fresh checkout; afterwards it loads it from its on-disk cache), while the node
        starts, and not at the first tick in the air, where it counted in the run's CPU per simulated second.
        """
        bodies.body_step(self.body.copy(), self.config.mass, self.inertia, self.inertia_inv, self.rho, self.thrust,
                         self.torque, np.zeros(3), self.config.gravity, self.config.dt)

    def _rest(self, pad: np.ndarray | None = None, pad_velocity: np.ndarray | None = None) -> None:
        """At rest on the ground: where it touched down, or on the pad (``pad``: its rest point, world),
        moving with it (``pad_velocity``, m/s).
        """
        self.body[:] = 0.0
        self.body[bodies.BS_POS:bodies.BS_POS + 3] = self.ground if pad is None else pad + self._on_pad
        if pad_velocity is not None:
            self.body[bodies.BS_VEL:bodies.BS_VEL + 3] = pad_velocity
        self.body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = (0.0, 0.0, math.sin(self.yaw / 2), math.cos(self.yaw / 2))

    # commands, as the bridge's services carry them

    def set_mode(self, name: str) -> tuple[bool, str]:
        """GUIDED or LAND."""
        name = name.upper()
        if name not in MODES:
            return False, f'unknown mode {name!r} for the built-in UAV; known: {", ".join(MODES)}'
        self.mode = name
        if name == 'GUIDED':
            self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3].copy()
        return True, f'mode {name}'

    def arm(self, arm: bool) -> tuple[bool, str]:
        """Arm or disarm (disarming in flight refused, as ArduCopter does)."""
        if not arm and self.armed and not self._on_ground():
            return False, 'disarm refused while flying'
        if arm and not self.armed:
            self.controller = StationController(self.config.mass, self.inertia, self.config.gravity)
            self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3].copy()
            self._riding = False
        if not arm and self.armed:
            self._touch_down(self._pad if self._over(self._pad) else None, None)
        self.armed = arm
        return True, 'armed' if arm else 'disarmed'

    def takeoff(self, altitude: float) -> tuple[bool, str]:
        """Climb ``altitude`` m above the current position (armed, GUIDED)."""
        if not self.armed or self.mode != 'GUIDED':
            return False, 'takeoff needs the UAV armed in GUIDED'
        self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3] + [0.0, 0.0, altitude]
        return True, 'takeoff accepted'

    def land(self) -> tuple[bool, str]:
        """Descend at ``land_speed`` where the UAV is, disarm on the ground."""
        self.mode = 'LAND'
        self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3].copy()
        return True, 'land accepted'

    def request(self, kind: str, mode: str = '', arm: bool = True, altitude: float = 0.0) -> tuple[bool, str]:
        """Carry out one request of the mission by name: set_mode, arm, takeoff or land."""
        if kind == 'set_mode':
            return self.set_mode(mode)
        if kind == 'arm':
            return self.arm(arm)
        if kind == 'takeoff':
            return self.takeoff(altitude)
        if kind == 'land':
            return self.land()
        return False, f'unknown request {kind!r}; known: set_mode, arm, takeoff, land'

    def setpoint(self, position) -> bool:
        """A position target in world, used in GUIDED while armed."""
        if self.mode != 'GUIDED' or not self.armed:
            return False
        self.reference = np.asarray(position, dtype=float).copy()
        return True

    # stepping

    def step(self, t: float, tether_force, pad=None) -> BuiltinUavState:
        """Advance to ``t`` (s) under the tether's force on the UAV (N, world) held over the step.

        ``pad``: where the CoM rests on the boat's landing pad at ``t`` (m, world), the ground
        under the UAV, moving linearly from its last value over the step; None: level ground.
        """
        force = np.asarray(tether_force, dtype=float)
        pad = None if pad is None else np.asarray(pad, dtype=float)
        before = self._pad if self._pad is not None else pad
        if self._t is not None and t > self._t:
            n_sub = max(1, math.ceil((t - self._t) / self.config.dt - 1e-9))
            dt = (t - self._t) / n_sub
            velocity = None if pad is None else (pad - before) / (t - self._t)
            for i in range(n_sub):
                self._advance(dt, force, None if pad is None else before + (pad - before) * ((i + 1) / n_sub), velocity)
        elif pad is not None and self._t is None and not self.armed and self._over(pad):
            self._touch_down(pad, None)
        self._pad = pad
        self._t = t
        if self.armed:
            state = self._body_state()
            ramp = [0.0, 0.0, -self.config.land_speed] if self.mode == 'LAND' else None
            moment = cross(self.rho, quaternion_rotation(state.quaternion, 'the UAV attitude').matrix.T @ force)
            self.thrust, self.torque = self.controller.step(t, state, self.reference, self.yaw, force, ramp, moment)
        b = self.body
        return BuiltinUavState(self.armed, self.mode, b[0:3].copy(), b[3:6].copy(), b[13:16].copy(), b[6:10].copy(),
                               b[10:13].copy())

    def _over(self, pad: np.ndarray | None) -> bool:
        """The body is within ``pad_radius`` of the pad horizontally."""
        return pad is not None and math.hypot(self.body[bodies.BS_POS] - pad[0],
                                              self.body[bodies.BS_POS + 1] - pad[1]) <= self.config.pad_radius

    def _touch_down(self, pad: np.ndarray | None, pad_velocity: np.ndarray | None) -> None:
        """Come to rest where the body is: on the pad (riding with it) or on the level ground."""
        position = self.body[bodies.BS_POS:bodies.BS_POS + 3]
        self._riding = pad is not None
        if self._riding:
            self._on_pad = np.array([position[0] - pad[0], position[1] - pad[1], 0.0])
        else:
            self.ground = np.array([position[0], position[1], self.start[2]])
        self._rest(pad, pad_velocity)

    def _advance(self, dt: float, force: np.ndarray, pad: np.ndarray | None, pad_velocity: np.ndarray | None) -> None:
        if not self.armed:
            self._ground_z = float(pad[2]) if self._riding else float(self.start[2])
            self._rest(pad if self._riding else None, pad_velocity if self._riding else None)
            return
        over = self._over(pad)
        self._ground_z = float(pad[2]) if over else float(self.start[2])
        if self.mode == 'LAND':
            self.reference[2] = max(self._ground_z - 0.2, self.reference[2] - self.config.land_speed * dt)
            if self._on_ground():
                self.armed = False
                self._touch_down(pad if over else None, pad_velocity if over else None)
                return
        bodies.body_step(self.body, self.config.mass, self.inertia, self.inertia_inv, self.rho, self.thrust,
                         self.torque, force, self.config.gravity, dt)
        if self.body[bodies.BS_POS + 2] < self._ground_z:          # the ground stops the body
            self.body[bodies.BS_POS + 2] = self._ground_z
            self.body[bodies.BS_VEL + 2] = max(0.0, self.body[bodies.BS_VEL + 2])

    def _on_ground(self) -> bool:
        return self.body[bodies.BS_POS + 2] <= self._ground_z + self.config.landed_below

    def _body_state(self) -> UavBodyState:
        b = self.body
        return UavBodyState(b[0:3].copy(), b[3:6].copy(), b[6:10].copy(), b[10:13].copy())
