"""The reel's own sensors: the passive guide arm and the tension inferred from motor current.

Guide arm (thesis Sec. 4.1, 6.1.3). The tether leaves the spool through a follower on
counter-weighted guide arms that turn freely about the spool axis; an absolute encoder
(US Digital MAE-3, 12 bit) reads the arm angle as the departure angle. The follower's
slot is wider than the tether: the tether bears on one side while paying out and on the
other while reeling in, so each reversal of the reel moves the reading by the slot's width
while the tether itself has not moved, the thesis's 20° dead-band ("periodic vertical
lines", Fig. 6.3). Here the reading is ``γ + s δ/2``, ``s = +1`` paying out and ``-1``
reeling in (which side reads high is a convention the thesis does not state), and ``s``
flips only once the payout speed exceeds ``switch_speed`` the other way, so a reel at rest
keeps its last side. The reading is quantised to the encoder's ``2π/2^bits``.

Tension from current (Sec. 4.1): the motor current gives the shaft torque ``N K_t i``; at
the drum radius ``r`` the tether tension that balances it, with the drivetrain's modelled
viscous and Coulomb friction compensated while the spool turns and the spool's inertia ``J``
compensated on the mean, is ``T = (-N K_t ī + b ω̄ + τ_c sgn ω̄ + J Δω/Δt)/r`` over a window
``Δt``: the drive's mean current ``ī``, the spool's mean rate ``ω̄`` (encoder angle over the
window) and the change ``Δω`` of its speed across the window (the motor's speed feedback at
the window's ends). The thesis does not say the prototype compensated the inertia. An
instantaneous estimate ``(-N K_t i + b ω + τ_c sgn ω)/r`` reads the spool's acceleration as
tension: every voltage step of the controller drives a current transient of about 3 ms, and
during the landing's reel-in those read ±36 N at each control tick with the true tension at
0-5 N, and up to 119 N (a false reel-in trip) against 4.5 N. Over the reel's 10 ms step the
mean balance holds exactly while the spool turns one way; over a step in which it reverses,
starts or stops the friction is unknown (static, or Coulomb of either sign: errors up to 31 N),
and the reel keeps the estimate of the step before (:class:`smart_reel.reel.ReelCore`). Compensating
``J ω̇`` on the *instantaneous* current does not work either: the current's transients are
shorter than any speed difference (errors of ±200 N).
"""

from __future__ import annotations

import math


class GuideArm:
    """Departure-angle reading of the passive guide arm with the follower's dead-band."""

    def __init__(self, deadband: float, bits: int = 12, switch_speed: float = 0.005) -> None:
        if not 0.0 <= deadband < math.pi:
            raise ValueError(f'guide-arm dead-band must be in [0, pi) rad, got {deadband}')
        self.deadband = deadband
        self.resolution = 2.0 * math.pi / 2**bits
        self.switch_speed = switch_speed
        self.side = 1

    def read(self, departure_angle: float, payout_rate: float) -> float:
        """Arm reading (rad) for the tether's true departure angle and payout rate (m/s)."""
        if payout_rate > self.switch_speed:
            self.side = 1
        elif payout_rate < -self.switch_speed:
            self.side = -1
        angle = departure_angle + 0.5 * self.side * self.deadband
        return math.floor(angle / self.resolution + 0.5) * self.resolution


def tension_from_current(mean_current: float, mean_spool_rate: float, speed_change: float, window: float,
                         radius: float, shaft_constant: float, inertia: float, viscous: float, coulomb: float,
                         moving_rate: float = 1e-3) -> float:
    """Tether tension (N) that balances the mean motor torque, the modelled friction and the spool's
    mean acceleration over ``window`` s (module docstring); currents in A, rates in rad/s.
    """
    torque = -shaft_constant * mean_current + inertia * speed_change / window
    if abs(mean_spool_rate) > moving_rate:
        torque += viscous * mean_spool_rate + math.copysign(coulomb, mean_spool_rate)
    return torque / radius
