"""The winch equation (thesis Eq. 7.26 / 7.42): one implementation for the plant and the smart reel.

Rotational balance at the spool shaft, paying out positive, with the payout rate
``Ldot = d ω`` (``d`` the radius the tether leaves the drum from):

    J ω̇ = u + d T_A - c ω - τ_c sgn ω

``J`` is the inertia at the shaft (drum, drive and the tether still wound on it), ``u`` the
drive torque (+ pays out), ``T_A`` the tether tension at the guide way, ``c`` viscous and
``τ_c`` Coulomb friction. A resting spool stays at rest while ``|u + d T_A|`` is at most the
static friction ``τ_s >= τ_c`` (stiction). Material leaves the drum with the rim speed, so
no momentum-flux term enters the balance.

One step of length ``h`` takes the viscous term implicitly,

    ω⁺ = (J ω + h (u + d T_A - τ_c sgn ω)) / (J + h c),

so a stiff damping (a voltage-driven motor's back-EMF reflected as ``c``) stays stable at
any step, and the torque a prescribed rate needs (:func:`required_torque`) is the same
balance solved for ``u``. A turning spool whose step would reverse its rate under Coulomb
friction stops instead (it then breaks away again only above ``τ_s``).

Plain Python on scalars (no numpy, no numba) so the smart reel calls it directly and the
plant's compiled stepper compiles it (:mod:`tether_dynamics.plant.bodies`).

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Eq. 7.26, 7.42; Sec. 6.1.4 (stiction).
"""

from __future__ import annotations

import math


def wound_inertia(mass_per_length: float, wound_length: float, radius: float) -> float:
    """Inertia (kg m²) of ``wound_length`` m of tether on a drum of ``radius`` m (the ``μ s_d d²`` of Eq. 7.42)."""
    return mass_per_length * wound_length * radius * radius


def spool_rate_step(rate: float, torque: float, tension: float, radius: float, inertia: float, viscous: float,
                    coulomb: float, static: float, stick_rate: float, h: float) -> float:
    """Spool rate (rad/s) after ``h`` s of Eq. 7.42 from ``rate`` (rad/s) under the drive ``torque`` (N m).

    Args:
        rate: ω at the start of the step (rad/s, + pays out).
        torque: u, drive torque at the shaft (N m, + pays out).
        tension: T_A, tether tension at the guide way (N).
        radius: d, radius the tether leaves the drum from (m).
        inertia: J, total inertia at the shaft (kg m²).
        viscous: c (N m s/rad).
        coulomb: τ_c (N m) while turning.
        static: τ_s (N m) to break away from rest.
        stick_rate: |ω| (rad/s) at or below which the spool counts as resting.
        h: step (s).

    Returns:
        ω after the step; exactly 0.0 while stiction holds the spool.
    """
    active = torque + radius * tension
    if abs(rate) <= stick_rate and abs(active) <= static:
        return 0.0
    direction = rate if rate != 0.0 else active
    friction = math.copysign(coulomb, direction)
    new_rate = (inertia * rate + h * (active - friction)) / (inertia + h * viscous)
    if coulomb > 0.0 and rate != 0.0 and new_rate * rate < 0.0:
        return 0.0
    return new_rate


def required_torque(rate: float, new_rate: float, tension: float, radius: float, inertia: float, viscous: float,
                    h: float) -> float:
    """Drive torque (N m) that takes the spool from ``rate`` to ``new_rate`` in ``h`` s (Eq. 7.42 for ``u``).

    The inverse of :func:`spool_rate_step` without Coulomb friction: the torque a prescribed
    spool rate asks of the drive.
    """
    return inertia * (new_rate - rate) / h - radius * tension + viscous * new_rate
