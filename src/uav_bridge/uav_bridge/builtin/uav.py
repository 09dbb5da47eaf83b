"""The built-in UAV: the plant's UAV rigid body flown by the station controller (no rclpy).

For runs without an autopilot. The body is ``tether_dynamics.plant.bodies.body_step`` (the
form of Eq. 7.44-7.45: thrust along body +z, body torque, gravity, the tether's force at the
attachment point), the same function the plant integrates; the controller is
:class:`uav_bridge.builtin.multirotor_control.StationController`. :class:`BuiltinUav` answers the
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
from numba import njit

from tether_dynamics.plant import bodies
from tether_models.constants import GRAVITY
from uav_bridge.builtin.multirotor_control import StationController

MODES = ('GUIDED', 'LAND')


@dataclass(frozen=True)
class BuiltinUavConfig:
    """The body, where it starts, and how it lands."""

    mass: float = 2.0                                   # kg
    inertia: tuple = ((0.03, 0.0, 0.0), (0.0, 0.03, 0.0), (0.0, 0.0, 0.05))   # kg m^2, body
    attach_offset: tuple = (0.0, 0.0, -0.1)             # m, tether attachment from the CoM, body FLU
    start: tuple = (0.0, 0.0, 0.0)                      # m, CoM at rest on the ground, world
    start_height: float = 0.0                           # m above start hovering at t = 0 (armed, GUIDED); 0: landed
    gravity: float = GRAVITY                            # m/s^2, the one g of tether_models.constants
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
        self.torque = np.zeros(3)                 # N m, body: the controller's, held over a step
        self._land_ramp = np.array([0.0, 0.0, -config.land_speed])   # m/s, world: the reference's rate in LAND
        self._rest()
        self.controller = StationController(config.mass, self.inertia, config.gravity)
        self._t: float | None = None
        if config.start_height > 0.0:
            self.body[bodies.BS_POS + 2] += config.start_height
            self.reference = self.body[bodies.BS_POS:bodies.BS_POS + 3].copy()
            self.armed = True

    def warm_up(self) -> None:
        """Fly a scratch copy of the body and controller one step, so that numba compiles
        :func:`_fly`, ``body_step`` and the controller now (seconds in a fresh checkout; afterwards
        it loads them from its on-disk cache), while the node starts, and not at the first tick in
        the air, where it counted in the run's CPU per simulated second.
        """
        cfg = self.config
        body, zero = self.body.copy(), np.zeros(3)
        _fly(body, 1, cfg.dt, zero, _NO_PAD, _NO_PAD, False, float(self.start[2]), cfg.pad_radius, False,
             self.reference.copy(), cfg.land_speed, cfg.landed_below, cfg.mass, self.inertia, self.inertia_inv,
             self.rho, self.thrust, self.torque, cfg.gravity)
        StationController(cfg.mass, self.inertia, cfg.gravity).step_body(
            0.0, body, self.reference.copy(), self.yaw, zero, self._land_ramp, self.rho, np.empty(3))

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
            velocity = None if pad is None else (pad - before) / (t - self._t)
            self._advance(n_sub, (t - self._t) / n_sub, force, before, pad, velocity)
        elif pad is not None and self._t is None and not self.armed and self._over(pad):
            self._touch_down(pad, None)
        self._pad = pad
        self._t = t
        if self.armed:
            ramp = self._land_ramp if self.mode == 'LAND' else None
            self.thrust = self.controller.step_body(t, self.body, self.reference, self.yaw, force, ramp, self.rho,
                                                    self.torque)
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

    def _advance(self, n_sub: int, dt: float, force: np.ndarray, before: np.ndarray | None, pad: np.ndarray | None,
                 pad_velocity: np.ndarray | None) -> None:
        """``n_sub`` body steps of ``dt``, the pad moving from ``before`` to ``pad``: armed, :func:`_fly`,
        and at a touch-down in LAND the disarmed rest from there on; at rest, only the last step's
        pad counts.
        """
        def pad_at(step: int) -> np.ndarray | None:
            """The pad at the end of body step ``step`` (from 0), as :func:`_fly` moves it."""
            return None if pad is None else before + (pad - before) * ((step + 1) / n_sub)

        first = 0
        if self.armed:
            cfg = self.config
            flown, self._ground_z = _fly(
                self.body, n_sub, dt, force, _NO_PAD if pad is None else before, _NO_PAD if pad is None else pad,
                pad is not None, float(self.start[2]), cfg.pad_radius, self.mode == 'LAND', self.reference,
                cfg.land_speed, cfg.landed_below, cfg.mass, self.inertia, self.inertia_inv, self.rho, self.thrust,
                self.torque, cfg.gravity)
            if flown == n_sub:
                return
            at = pad_at(flown)
            over = self._over(at)
            self.armed = False
            self._touch_down(at if over else None, pad_velocity if over else None)
            first = flown + 1
        if first < n_sub:
            last = pad_at(n_sub - 1)
            self._ground_z = float(last[2]) if self._riding else float(self.start[2])
            self._rest(last if self._riding else None, pad_velocity if self._riding else None)

    def _on_ground(self) -> bool:
        return self.body[bodies.BS_POS + 2] <= self._ground_z + self.config.landed_below


_NO_PAD = np.zeros(3)


@njit(cache=True)
def _fly(body, n_sub, dt, force, pad_from, pad_to, use_pad, start_z, pad_radius, land, reference, land_speed,
         landed_below, mass, inertia, inertia_inv, rho, thrust, torque, gravity):
    """``n_sub`` steps of ``dt`` of the armed body (``bodies.body_step``) under the held commands and
    tether force. At each step the ground is the pad (moving linearly from ``pad_from`` to ``pad_to``)
    within ``pad_radius`` of it horizontally, else level at ``start_z``; it stops the body. In LAND the
    reference descends at ``land_speed`` to 0.2 m below the ground, and a body within ``landed_below``
    of the ground has landed. Returns the steps flown (``n_sub``, or the step at which it landed, before
    that step) and the ground's height at the last step flown or the landing.
    """
    ground_z = start_z
    for i in range(n_sub):
        ground_z = start_z
        if use_pad:
            fraction = (i + 1) / n_sub
            pad_x = pad_from[0] + (pad_to[0] - pad_from[0]) * fraction
            pad_y = pad_from[1] + (pad_to[1] - pad_from[1]) * fraction
            if math.hypot(body[bodies.BS_POS] - pad_x, body[bodies.BS_POS + 1] - pad_y) <= pad_radius:
                ground_z = pad_from[2] + (pad_to[2] - pad_from[2]) * fraction
        if land:
            reference[2] = max(ground_z - 0.2, reference[2] - land_speed * dt)
            if body[bodies.BS_POS + 2] <= ground_z + landed_below:
                return i, ground_z
        bodies.body_step(body, mass, inertia, inertia_inv, rho, thrust, torque, force, gravity, dt)
        if body[bodies.BS_POS + 2] < ground_z:          # the ground stops the body
            body[bodies.BS_POS + 2] = ground_z
            body[bodies.BS_VEL + 2] = max(0.0, body[bodies.BS_VEL + 2])
    return n_sub, ground_z
