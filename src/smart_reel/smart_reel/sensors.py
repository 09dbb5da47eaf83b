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
viscous and Coulomb friction compensated while the spool turns, is
``T = (-N K_t i + b ω + τ_c sgn ω)/r``. The spool's inertia is not compensated (the thesis
does not say the prototype did), so accelerations show in the estimate: with the drive at its
current limit, ``N K_t i_max/r`` ≈ 600 N. Compensating ``J ω̇`` from the encoder does not help:
the drive's transients last about 3 ms, and encoder differences over 1-3 ms lag them (on the
recorded outdoor flight that left peaks of 216-273 N). The catenary controller instead keeps
the drive off its current limit (:mod:`smart_reel.controller`, step 5).
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


def tension_from_current(current: float, spool_rate: float, radius: float, shaft_constant: float,
                         viscous: float, coulomb: float, moving_rate: float = 1e-3) -> float:
    """Tether tension (N) that balances the motor torque and the modelled friction."""
    torque = -shaft_constant * current
    if abs(spool_rate) > moving_rate:
        torque += viscous * spool_rate + math.copysign(coulomb, spool_rate)
    return torque / radius
