"""The spool drive: motor, gearbox, drum and wound tether against the tether's pull.

The winch equation of the thesis (Eq. 7.42, :mod:`tether_dynamics.winch`, the same
implementation the tether plant steps) with the drive's inertia and friction:

    J(L) ω̇ = N K_t i + T r(L) - b ω - τ_c sgn ω,        J(L) = J_drum + J_wound(L) + N² J_m

with ``T`` the tether tension at the guide way, ``r(L)`` the radius it leaves the drum from
(:class:`~smart_reel.spool.SpoolGeometry`), viscous friction ``b`` and Coulomb friction
``τ_c``. A resting spool stays at rest while the net torque ``|N K_t i + T r|`` is at most
the static friction ``τ_s ≥ τ_c`` (stiction, the threshold the thesis's taut controller had
to run above, Sec. 6.1.4). A brake holds the spool at rest.

Why the drive is integrated here and not in the tether plant: a voltage-driven motor damps
the spool by ``(N K)²/R`` (10.7 N m s/rad with the defaults) against an inertia of
about 0.03-0.05 kg m², a time constant of 3-5 ms. Exchanging torque and spool rate between
two nodes at 100 Hz, one step apart, multiplies the spool rate by ``-h (N K)²/(R J) ≈ -2...-4``
per step: the loop is unstable. So the stiff electromechanics are integrated here in
sub-steps of at most ``max_substep`` (exact current exponential, implicit viscous term),
with the tether tension of the last plant step as the load, and the plant receives the
resulting payout over the step (``ReelCommand.CONTROL_SPOOL_RATE``). The remaining loop
(tension → spool → payout → tension) crosses the delay through the tether's compliance:
slow against the step while the tether hangs, but a taut tether is a stiff spring, so
the pull is moved along the tether's stiffness to each sub-step's length
(:mod:`smart_reel.tension_model`).

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 4.1, 6.1.4, Eq. 7.42.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from smart_reel.motor import MotorParameters
from smart_reel.motor import current_command
from smart_reel.motor import current_step
from smart_reel.spool import SpoolGeometry
from tether_dynamics.winch import spool_rate_step

VOLTAGE = 'voltage'
CURRENT = 'current'
BRAKE = 'brake'
DRIVES = (VOLTAGE, CURRENT, BRAKE)


@dataclass(frozen=True)
class Friction:
    """Drivetrain friction at the spool shaft."""

    viscous: float = 0.02
    """b (N m s/rad)."""
    coulomb: float = 0.25
    """τ_c (N m), while turning."""
    static: float = 0.35
    """τ_s (N m), to break away from rest; at least ``coulomb``."""

    def __post_init__(self) -> None:
        if min(self.viscous, self.coulomb, self.static) < 0.0 or self.static < self.coulomb:
            raise ValueError(f'friction needs viscous, coulomb >= 0 and static >= coulomb, got {self}')


@dataclass
class WinchState:
    """State of the spool drive."""

    spool_angle: float = 0.0
    """θ (rad) from the start of the run, + pays out."""
    spool_rate: float = 0.0
    """ω (rad/s), + pays out."""
    current: float = 0.0
    """Winding current (A)."""
    charge: float = 0.0
    """∫ current dt (C) from the start of the run: mean currents over any window."""
    voltage: float = 0.0
    """Winding voltage applied by the drive in the last sub-step (V)."""
    current_limited: bool = False
    """The drive clipped the current in the last step."""
    stuck: bool = True
    """The spool is held by stiction or the brake."""


class Winch:
    """Spool drive stepped with explicit time: ``step(dt, drive, command, tension)``.

    ``drive`` is :data:`VOLTAGE` (``command`` in V), :data:`CURRENT` (A, the drive's torque
    mode) or :data:`BRAKE` (``command`` ignored).
    """

    def __init__(self, motor: MotorParameters, spool: SpoolGeometry, friction: Friction, drum_inertia: float,
                 initial_length: float, max_substep: float = 1e-3, stick_rate: float = 1e-3) -> None:
        if not 0.0 < initial_length <= spool.capacity:
            raise ValueError(f'initial deployed length {initial_length} m outside (0, {spool.capacity}] m')
        self.motor = motor
        self.spool = spool
        self.friction = friction
        self.drum_inertia = drum_inertia
        self.initial_length = initial_length
        self.max_substep = max_substep
        self.stick_rate = stick_rate
        self.state = WinchState()
        self.deployed = initial_length

    def inertia(self) -> float:
        """Total inertia at the spool shaft (kg m²) at the current deployed length."""
        return self.drum_inertia + self.spool.wound_inertia(self.deployed) + self.motor.reflected_inertia

    def step(self, dt: float, drive: str, command: float, tension: float, stiffness: float = 0.0,
             reference_length: float | None = None) -> WinchState:
        """Advance ``dt`` seconds with the drive command against the tether's pull.

        The pull is ``tension`` (N) at ``reference_length`` (m, default: the length at the
        start of the step) moved along ``stiffness`` (N/m, ``-∂T/∂L``) to the length of each
        sub-step, and never below zero (:mod:`smart_reel.tension_model`). The drum radius and
        the inertia are those at the start of the step (they change only when the tether
        crosses into another layer).
        """
        if drive not in DRIVES:
            raise ValueError(f'drive must be one of {DRIVES}, got {drive!r}')
        n = max(1, math.ceil(dt / self.max_substep - 1e-9))
        h = dt / n
        s = self.state
        m = self.motor
        f = self.friction
        limited = False
        r = self.spool.radius(self.deployed)
        j = self.inertia()
        start_angle = s.spool_angle
        offset = self.deployed - (self.deployed if reference_length is None else reference_length)
        for _ in range(n):
            if drive == VOLTAGE:
                s.current = current_step(m, s.current, command, s.spool_rate, h)
                s.voltage = min(max(command, -m.supply_voltage), m.supply_voltage)
                limited |= abs(s.current) >= m.current_limit
            elif drive == CURRENT:
                s.current = current_command(m, command, s.spool_rate)
                s.voltage = s.current * m.resistance + m.shaft_constant * s.spool_rate
                limited |= s.current != command
            else:
                s.current = 0.0
                s.voltage = 0.0
            if drive == BRAKE:
                new_rate = 0.0
            else:
                pull = max(0.0, tension - stiffness * (offset + r * (s.spool_angle - start_angle)))
                new_rate = spool_rate_step(s.spool_rate, m.shaft_constant * s.current, pull, r, j, f.viscous,
                                           f.coulomb, f.static, self.stick_rate, h)
            s.charge += h * s.current
            s.spool_angle += 0.5 * h * (s.spool_rate + new_rate)
            s.spool_rate = new_rate
            s.stuck = new_rate == 0.0
        self.deployed = self.spool.deployed_length(self.initial_length, s.spool_angle)
        s.current_limited = limited
        return s
