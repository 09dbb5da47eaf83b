"""Quad-X rotors driven by ArduPilot's motor PWM: thrust, torque and motor lag (no rclpy).

The motor model, per rotor i (documented values in :class:`QuadXConfig`):

* command ``u = (pwm - pwm_min) / (pwm_max - pwm_min)``, cut to [0, 1];
* the ESC sets a normalised rotor speed ``s`` whose steady value makes the steady thrust
  follow the curve ArduPilot linearises with ``MOT_THST_EXPO = e``:
  ``T_ss = T_max ((1 - e) u + e u^2)``, i.e. ``s_ss = sqrt((1 - e) u + e u^2)``;
* the rotor speed lags its steady value with the motor time constant tau,
  ``ds/dt = (s_ss - s) / tau`` (integrated exactly over a step with the command held);
* thrust ``T = T_max s^2`` along the body's up axis (FRD -z), reaction torque
  ``Q = c_q T`` about it, opposite to the propeller's spin.

Geometry and order are ArduCopter's quad X (FRAME_CLASS 1, FRAME_TYPE 1): channel 1 front
right (CCW propeller), 2 rear left (CCW), 3 front left (CW), 4 rear right (CW), each at
``arm`` from the centre on the diagonals. A CCW propeller (seen from above) drives the body
clockwise, i.e. a positive yaw torque about FRD z (nose right), as ArduPilot's yaw factors.

The default vehicle is of the thesis's class (Sec. 5.3: a modified DJI S900, 900 mm
wheelbase, carrying the tether): 6 kg, 0.45 m arms, 36 N per rotor at full command (thrust
to weight 2.4 without the tether, hover near 0.4 of full thrust as copter.parm's
MOT_THST_HOVER 0.39 assumes), c_q = 0.016 m (15-inch propellers), tau = 0.04 s. The inertia
is the estimate of 4 rotor assemblies of 0.35 kg at the arm tips plus a 4.6 kg central body
of 0.15 m radius: (0.17, 0.17, 0.34) kg m².
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uav_bridge.frames import frd_to_flu

# Motor positions (forward, right) as multiples of arm / sqrt(2), and spin: +1 CCW propeller.
QUAD_X_LAYOUT = ((1.0, 1.0, 1.0), (-1.0, -1.0, 1.0), (1.0, -1.0, -1.0), (-1.0, 1.0, -1.0))


@dataclass(frozen=True)
class QuadXConfig:
    """The vehicle: rotors (see the module docstring) and its rigid body."""

    mass: float = 6.0                                   # kg
    inertia: tuple = ((0.17, 0.0, 0.0), (0.0, 0.17, 0.0), (0.0, 0.0, 0.34))   # kg m^2, body
    arm: float = 0.45                                   # m, centre to each rotor axis
    max_thrust: float = 36.0                            # N per rotor at full command
    thrust_expo: float = 0.65                           # MOT_THST_EXPO the thrust curve follows
    torque_ratio: float = 0.016                         # m, rotor reaction torque per thrust
    time_constant: float = 0.04                         # s, rotor speed lag
    pwm_min: float = 1000.0                             # µs, zero command
    pwm_max: float = 2000.0                             # µs, full command

    def __post_init__(self) -> None:
        for name in ('mass', 'arm', 'max_thrust', 'torque_ratio', 'time_constant'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be a positive number, got {value!r}')
        if not 0.0 <= self.thrust_expo <= 1.0:
            raise ValueError(f'thrust_expo must lie in [0, 1], got {self.thrust_expo!r}')
        if not self.pwm_max > self.pwm_min:
            raise ValueError(f'pwm_max ({self.pwm_max}) must exceed pwm_min ({self.pwm_min})')

    def hover_command(self, load: float) -> float:
        """The command u (0..1) at which the four rotors hold ``load`` (N) in steady state."""
        fraction = load / (4.0 * self.max_thrust)
        e = self.thrust_expo
        if e == 0.0:
            return fraction
        return (-(1.0 - e) + math.sqrt((1.0 - e) ** 2 + 4.0 * e * fraction)) / (2.0 * e)


class QuadXMotors:
    """The four rotors' speeds, stepped with held PWM commands."""

    def __init__(self, config: QuadXConfig) -> None:
        self.config = config
        d = config.arm / math.sqrt(2.0)
        layout = np.asarray(QUAD_X_LAYOUT)
        self.position_frd = np.column_stack([layout[:, 0] * d, layout[:, 1] * d, np.zeros(4)])
        self.spin = layout[:, 2]
        # Torque about the centre of mass per rotor thrust: r x (0, 0, -T) plus the reaction about FRD z.
        self.torque_per_thrust = frd_to_flu(np.vstack([-self.position_frd[:, 1], self.position_frd[:, 0],
                                                       config.torque_ratio * self.spin]))
        self.speed = np.zeros(4)                        # normalised rotor speed s

    def reset(self) -> None:
        """Rotors at rest."""
        self.speed[:] = 0.0

    def commands(self, pwm) -> np.ndarray:
        """Command u (0..1) of the four motors from the first four channels (µs)."""
        c = self.config
        return np.clip((np.asarray(pwm[:4], dtype=float) - c.pwm_min) / (c.pwm_max - c.pwm_min), 0.0, 1.0)

    def steady_speed(self, pwm) -> np.ndarray:
        """The normalised rotor speeds the PWM holds in steady state."""
        u = self.commands(pwm)
        e = self.config.thrust_expo
        return np.sqrt((1.0 - e) * u + e * u * u)

    def step(self, steady: np.ndarray, dt: float) -> None:
        """Advance the rotor speeds by ``dt`` (s) towards ``steady`` (:meth:`steady_speed`)."""
        self.speed += (steady - self.speed) * (1.0 - math.exp(-dt / self.config.time_constant))

    def thrusts(self) -> np.ndarray:
        """Thrust of each rotor, N."""
        return self.config.max_thrust * self.speed ** 2

    def wrench_flu(self) -> tuple[float, np.ndarray]:
        """Total thrust (N, along body FLU +z) and torque about the centre of mass (N m, body FLU)."""
        thrust = self.thrusts()
        return float(thrust.sum()), self.torque_per_thrust @ thrust
