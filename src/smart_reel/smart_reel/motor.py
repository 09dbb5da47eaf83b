"""DC servo motor of the smart reel's spool drive (thesis Sec. 4.1, Table 5.1).

The prototype's spool motor is a Moog Animatics SM23165MT, a NEMA 23 brushless servo with
its own drive, run by the reel computer through a gearbox into the spool (Sec. 4.1). It is
modelled as the usual permanent-magnet DC motor seen from its drive's terminals:

* electrical: ``L di/dt = v - R i - K_e ω_m`` (back-EMF ``K_e ω_m``),
* torque: ``τ_m = K_t i`` with ``K_t = K_e`` in SI units,
* the drive limits the winding current to ``±i_max`` and the voltage to the supply,
* the gearbox (ratio ``N``) gives ``τ = N K_t i`` and ``ω_m = N ω`` at the spool shaft.

Within a step of length ``h`` with the motor speed held, the current follows the exact
exponential towards ``(v - K_e ω_m)/R`` with time constant ``L/R``.

The default values are of the motor's class (NEMA 23 integrated servo, 48 V supply), not
measured on the prototype; each parameter's source is in :mod:`smart_reel.reel_params`.

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 4.1 and Table 5.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class MotorParameters:
    """Motor, drive and gearbox constants (SI)."""

    resistance: float = 1.5
    """Winding resistance R (Ω)."""
    inductance: float = 2.5e-3
    """Winding inductance L (H)."""
    torque_constant: float = 0.10
    """K_t = K_e (N m/A = V s/rad)."""
    rotor_inertia: float = 1.2e-5
    """Rotor inertia J_m (kg m²)."""
    current_limit: float = 12.0
    """Drive's peak current limit i_max (A)."""
    supply_voltage: float = 48.0
    """Drive supply; the largest winding voltage (V)."""
    gear_ratio: float = 40.0
    """Motor turns per spool turn N (1)."""

    def __post_init__(self) -> None:
        for name in ('resistance', 'inductance', 'torque_constant', 'rotor_inertia', 'current_limit',
                     'supply_voltage', 'gear_ratio'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'motor {name} must be a positive number, got {value}')

    @property
    def shaft_constant(self) -> float:
        """Spool-shaft torque per ampere, ``N K_t`` (N m/A); also back-EMF per spool rad/s."""
        return self.gear_ratio * self.torque_constant

    @property
    def reflected_inertia(self) -> float:
        """Rotor inertia seen at the spool shaft, ``N² J_m`` (kg m²)."""
        return self.gear_ratio**2 * self.rotor_inertia

    @property
    def voltage_step(self) -> float:
        """Largest step of the winding voltage (V) whose first current, ``Δv/R``, stays within ``i_max``."""
        return self.resistance * self.current_limit

    @property
    def back_emf_damping(self) -> float:
        """Spool-shaft damping of a voltage-driven motor, ``(N K)²/R`` (N m s/rad)."""
        return self.shaft_constant**2 / self.resistance


def current_step(params: MotorParameters, current: float, voltage: float, spool_rate: float, h: float) -> float:
    """Winding current after ``h`` seconds at ``voltage`` with the spool rate held (exact).

    The drive clips the voltage to the supply and the current to ``±current_limit``.
    """
    v = min(max(voltage, -params.supply_voltage), params.supply_voltage)
    target = (v - params.shaft_constant * spool_rate) / params.resistance
    decay = math.exp(-h * params.resistance / params.inductance)
    i = target + (current - target) * decay
    return min(max(i, -params.current_limit), params.current_limit)


def current_command(params: MotorParameters, current: float, spool_rate: float) -> float:
    """Winding current the drive's current loop achieves for a commanded ``current``.

    The loop is taken as ideal within the voltage it has left over the back-EMF and
    the current limit (the SmartMotor's torque mode).
    """
    emf = params.shaft_constant * spool_rate
    low = (-params.supply_voltage - emf) / params.resistance
    high = (params.supply_voltage - emf) / params.resistance
    i = min(max(current, low), high)
    return min(max(i, -params.current_limit), params.current_limit)


def steady_state_rate(params: MotorParameters, voltage: float, load_torque: float = 0.0,
                      viscous: float = 0.0, coulomb: float = 0.0) -> float:
    """Closed-form steady spool rate (rad/s) under ``voltage`` against a spool ``load_torque``.

    ``load_torque`` (N m) opposes positive rotation; ``viscous`` (N m s/rad) and ``coulomb``
    (N m) are the drivetrain's friction at the spool shaft. Solves
    ``N K (v - N K ω)/R - load - b ω - τ_c sgn ω = 0`` for a moving spool below the current limit.
    """
    k = params.shaft_constant
    drive = k * voltage / params.resistance - load_torque
    if abs(drive) <= coulomb:
        return 0.0
    return (drive - math.copysign(coulomb, drive)) / (k * k / params.resistance + viscous)


def stall_torque(params: MotorParameters, voltage: float) -> float:
    """Closed-form spool-shaft torque (N m) at zero speed: ``N K min(v/R, i_max)``."""
    v = min(max(voltage, -params.supply_voltage), params.supply_voltage)
    i = min(max(v / params.resistance, -params.current_limit), params.current_limit)
    return params.shaft_constant * i
