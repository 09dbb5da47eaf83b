"""Cascaded position/attitude controller of a multirotor that holds a station (no rclpy).

The controller of the built-in UAV: it turns a position reference into the collective
thrust (N, along body +z) and body torque (N m, FLU) the plant's UAV rigid body takes
(``tether_dynamics.plant.bodies.body_step``). Two loops:

* position (outer): a PID on the ENU position error gives the desired force
  ``F = m (Kp e_p + Ki ∫e_p + Kd e_v + g e3) - f_tether`` (e_v against the reference's rate), with the tether's measured force
  on the UAV as feed-forward when it is given; the thrust is ``F · R e3`` and the desired
  body z axis ``F / |F|``, tilt limited to ``max_tilt``;
* attitude (inner): the geometric controller on SO(3) of Lee, Leok and McClamroch (2010),
  ``tau = -K_R e_R - K_W e_W + W x J W - M_tether`` with ``e_R = vee(R_d^T R - R^T R_d) / 2``
  and ``e_W = W`` (station keeping: no commanded body rate); ``M_tether``, the tether's
  moment about the centre of mass when it is given, is fed forward (without it a tether
  pull at an attachment point off the centre of mass leaves a steady attitude error, and
  the tilt it causes a steady position error).

References:
    T. Lee, M. Leok, N. H. McClamroch, "Geometric tracking control of a quadrotor UAV on
    SE(3)", 49th IEEE Conference on Decision and Control, 2010, pp. 5420-5425, Eq. (15)-(16).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from tether_common.rotation import quaternion_rotation
from tether_dynamics.plant import bodies


@dataclass(frozen=True)
class ControllerGains:
    """Gains and limits; the defaults hold a 2 kg multirotor (the plant's default UAV)."""

    kp: float = 4.0                 # 1/s^2, position
    ki: float = 0.8                 # 1/s^3, position integral
    kd: float = 3.5                 # 1/s, velocity
    k_r: float = 1.2                # N m/rad, attitude (scaled for inertia ~0.03 kg m^2)
    k_w: float = 0.25               # N m s/rad, body rate
    max_tilt: float = math.radians(35.0)   # rad, largest commanded tilt of the thrust axis
    max_thrust: float = 60.0        # N
    integral_limit: float = 2.0     # m s, anti-windup bound on each axis of ∫e_p


@dataclass(frozen=True)
class UavBodyState:
    """State of the UAV rigid body, as the plant reports it."""

    position: np.ndarray            # m, centre of mass, world (ENU)
    velocity: np.ndarray            # m/s, world
    quaternion: np.ndarray          # (x, y, z, w), body (FLU) -> world
    angular_velocity: np.ndarray    # rad/s, body


class StationController:
    """The cascaded controller (see the module docstring), stepped with explicit time."""

    def __init__(self, mass: float, inertia, gravity: float, gains: ControllerGains = ControllerGains()) -> None:
        self.mass = mass
        self.inertia = np.asarray(inertia, dtype=float)
        self.gravity = gravity
        self.gains = gains
        self._gains = np.array([gains.kp, gains.ki, gains.kd, gains.k_r, gains.k_w, math.tan(gains.max_tilt),
                                gains.max_thrust, gains.integral_limit])
        self.integral = np.zeros(3)
        self._t: float | None = None

    def step(self, t: float, state: UavBodyState, reference, yaw: float = 0.0,
             tether_force=None, reference_velocity=None, tether_moment=None) -> tuple[float, np.ndarray]:
        """Return (thrust N, body torque N m) holding ``reference`` (m, world) at heading ``yaw`` (rad, ENU).

        ``tether_force`` (N, world) is the tether's measured force on the UAV, fed forward;
        ``reference_velocity`` (m/s, world) the reference's rate of change (a ramp), zero if None;
        ``tether_moment`` (N m, body) the tether's moment about the centre of mass, fed forward.
        """
        quaternion = quaternion_rotation(state.quaternion, 'the UAV attitude').q
        body = np.zeros(bodies.BS_SIZE)
        body[bodies.BS_POS:bodies.BS_POS + 3] = state.position
        body[bodies.BS_VEL:bodies.BS_VEL + 3] = state.velocity
        body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = quaternion
        body[bodies.BS_OMEGA:bodies.BS_OMEGA + 3] = state.angular_velocity
        moment = _ZERO if tether_moment is None else np.asarray(tether_moment, dtype=float)
        torque = np.empty(3)
        thrust = self._step(t, body, reference, yaw, tether_force, reference_velocity, moment, _ZERO, torque)
        return thrust, torque

    def step_body(self, t: float, body: np.ndarray, reference: np.ndarray, yaw: float, tether_force: np.ndarray,
                  reference_velocity: np.ndarray | None, attach_offset: np.ndarray, torque: np.ndarray) -> float:
        """:meth:`step` on a body state vector (``tether_dynamics.plant.bodies``' layout, a unit
        quaternion), with the tether's moment about the centre of mass fed forward from where it
        pulls, ``attach_offset`` (m, body): ``attach_offset x (R^T tether_force)``. Writes the
        torque (N m, body) into ``torque`` and returns the thrust (N).
        """
        return self._step(t, body, reference, yaw, tether_force, reference_velocity, _ZERO, attach_offset, torque)

    def _step(self, t, body, reference, yaw, tether_force, reference_velocity, moment, attach_offset, torque) -> float:
        dt = 0.0 if self._t is None else t - self._t
        self._t = t
        return _control(body, np.asarray(reference, dtype=float),
                        _ZERO if reference_velocity is None else np.asarray(reference_velocity, dtype=float),
                        float(yaw), _ZERO if tether_force is None else np.asarray(tether_force, dtype=float),
                        moment, attach_offset, self.integral, dt, self.mass, self.inertia, self.gravity, self._gains,
                        torque)


_ZERO = np.zeros(3)
"""An absent feed-forward or reference rate: subtracting it changes nothing."""


@njit(cache=True)
def _control(body, reference, reference_velocity, yaw, tether_force, moment, attach_offset, integral, dt, mass,
             inertia, gravity, gains, torque):
    """One step of both loops (module docstring; Lee et al. Eq. (10), (15), (16)); the thrust is returned,
    the torque written to ``torque``, ``integral`` advanced. ``moment``: the tether's moment (body),
    or, added to it, ``attach_offset x (R^T tether_force)``.
    """
    kp, ki, kd, k_r, k_w, tan_tilt, max_thrust, integral_limit = gains
    q = body[bodies.BS_QUAT:bodies.BS_QUAT + 4]
    x, y, z, w = q[0], q[1], q[2], q[3]
    rotation = np.array([[1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)],
                         [2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)],
                         [2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)]])
    force = np.empty(3)
    for c in range(3):
        error = reference[c] - body[bodies.BS_POS + c]
        integral[c] = min(max(integral[c] + dt * error, -integral_limit), integral_limit)
        accel = kp * error + ki * integral[c] + kd * (reference_velocity[c] - body[bodies.BS_VEL + c])
        if c == 2:
            accel += gravity
        force[c] = mass * accel - tether_force[c]
    vertical = max(force[2], 1e-6)
    horizontal = math.hypot(force[0], force[1])
    limit = vertical * tan_tilt
    if horizontal > limit:
        force[0] *= limit / horizontal
        force[1] *= limit / horizontal
    thrust = min(max(force[0] * rotation[0, 2] + force[1] * rotation[1, 2] + force[2] * rotation[2, 2], 0.0),
                 max_thrust)
    norm = math.sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2])
    b3 = force / norm
    b2 = _cross(b3, np.array([math.cos(yaw), math.sin(yaw), 0.0]))
    b2 /= math.sqrt(b2[0] * b2[0] + b2[1] * b2[1] + b2[2] * b2[2])
    b1 = _cross(b2, b3)
    desired = np.empty((3, 3))
    for r in range(3):
        desired[r, 0], desired[r, 1], desired[r, 2] = b1[r], b2[r], b3[r]
    error_r = np.array([0.5 * _skew_part(desired, rotation, 2, 1), 0.5 * _skew_part(desired, rotation, 0, 2),
                        0.5 * _skew_part(desired, rotation, 1, 0)])
    omega = body[bodies.BS_OMEGA:bodies.BS_OMEGA + 3]
    gyro = _cross(omega, _times(inertia, omega, False))
    pull = _cross(attach_offset, _times(rotation, tether_force, True))
    for c in range(3):
        torque[c] = -k_r * error_r[c] - k_w * omega[c] + gyro[c] - moment[c] - pull[c]
    return thrust


@njit(cache=True)
def _cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@njit(cache=True)
def _times(matrix, vector, transposed):
    """``matrix @ vector``, or ``matrix.T @ vector``, of a 3x3 matrix."""
    out = np.zeros(3)
    for r in range(3):
        for c in range(3):
            out[r] += (matrix[c, r] if transposed else matrix[r, c]) * vector[c]
    return out


@njit(cache=True)
def _skew_part(desired, rotation, i, j):
    """Element (i, j) of ``desired.T @ rotation - rotation.T @ desired`` (Lee et al. Eq. (10) before the vee)."""
    total = 0.0
    for k in range(3):
        total += desired[k, i] * rotation[k, j] - rotation[k, i] * desired[k, j]
    return total
