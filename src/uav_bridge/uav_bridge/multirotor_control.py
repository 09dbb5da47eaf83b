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

from tether_dynamics.plant.ends import cross
from tether_common.rotation import quaternion_rotation

E3 = np.array([0.0, 0.0, 1.0])


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
        self.integral = np.zeros(3)
        self._t: float | None = None

    def step(self, t: float, state: UavBodyState, reference, yaw: float = 0.0,
             tether_force=None, reference_velocity=None, tether_moment=None) -> tuple[float, np.ndarray]:
        """Return (thrust N, body torque N m) holding ``reference`` (m, world) at heading ``yaw`` (rad, ENU).

        ``tether_force`` (N, world) is the tether's measured force on the UAV, fed forward;
        ``reference_velocity`` (m/s, world) the reference's rate of change (a ramp), zero if None;
        ``tether_moment`` (N m, body) the tether's moment about the centre of mass, fed forward.
        """
        g = self.gains
        dt = 0.0 if self._t is None else t - self._t
        self._t = t
        error = np.asarray(reference, dtype=float) - state.position
        self.integral = np.clip(self.integral + dt * error, -g.integral_limit, g.integral_limit)
        velocity_error = (np.zeros(3) if reference_velocity is None else np.asarray(reference_velocity, dtype=float)) \
            - state.velocity
        accel = g.kp * error + g.ki * self.integral + g.kd * velocity_error + self.gravity * E3
        force = self.mass * accel
        if tether_force is not None:
            force = force - np.asarray(tether_force, dtype=float)
        force = self._limit_tilt(force)
        rotation = quaternion_rotation(state.quaternion, 'the UAV attitude').matrix
        thrust = min(max(float(force @ rotation[:, 2]), 0.0), g.max_thrust)
        desired = self._desired_attitude(force, yaw)
        error_r = 0.5 * _vee(desired.T @ rotation - rotation.T @ desired)    # Lee et al. Eq. (10)
        omega = np.asarray(state.angular_velocity, dtype=float)
        torque = -g.k_r * error_r - g.k_w * omega + cross(omega, self.inertia @ omega)   # Eq. (16)
        if tether_moment is not None:
            torque = torque - np.asarray(tether_moment, dtype=float)
        return thrust, torque

    def _limit_tilt(self, force: np.ndarray) -> np.ndarray:
        vertical = max(force[2], 1e-6)
        horizontal = np.hypot(force[0], force[1])
        limit = vertical * math.tan(self.gains.max_tilt)
        if horizontal > limit:
            force = force.copy()
            force[:2] *= limit / horizontal
        return force

    @staticmethod
    def _desired_attitude(force: np.ndarray, yaw: float) -> np.ndarray:
        b3 = force / math.sqrt(force.dot(force))
        heading = np.array([math.cos(yaw), math.sin(yaw), 0.0])
        b2 = cross(b3, heading)
        b2 /= math.sqrt(b2.dot(b2))
        return np.column_stack([cross(b2, b3), b2, b3])


def _vee(matrix: np.ndarray) -> np.ndarray:
    return np.array([matrix[2, 1], matrix[0, 2], matrix[1, 0]])
