"""Safety trips of the smart reel (thesis Ch. 4: "safety precautions to prevent catastrophic forces").

Paying out is stopped when the tether's lowest point comes within ``min_clearance`` of the
deck or the water, or when the guide arm reads a departure angle below
``min_departure_angle`` (the tether leaving the reel downward, towards the deck); reeling
in is stopped when the tension estimate exceeds ``max_tension``. A trip holds the reel
(brake) for as long as the controller asks for the blocked direction and the condition
lasts; each trip has a reason, and every rising edge is counted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SafetyLimits:
    """Trip thresholds."""

    min_clearance: float = 0.2
    """m, lowest point above the deck or the water."""
    min_departure_angle: float = -0.35
    """rad, guide-arm reading."""
    max_tension: float = 80.0
    """N, tension estimate while reeling in."""


class SafetyMonitor:
    """Checks a commanded direction against the limits; remembers the trip count."""

    def __init__(self, limits: SafetyLimits) -> None:
        self.limits = limits
        self.reason = ''
        self.trips = 0

    def check(self, direction: float, clearance: float, arm_angle: float, tension: float) -> str:
        """Return the trip reason for a command of sign ``direction`` (+ pays out), or ''."""
        lim = self.limits
        reason = ''
        if direction > 0.0:
            if math.isfinite(clearance) and clearance < lim.min_clearance:
                reason = f'payout stopped: lowest point {clearance:.3f} m above deck/water < {lim.min_clearance:g} m'
            elif math.isfinite(arm_angle) and arm_angle < lim.min_departure_angle:
                reason = (f'payout stopped: departure angle {math.degrees(arm_angle):.1f} deg < '
                          f'{math.degrees(lim.min_departure_angle):g} deg')
        elif direction < 0.0 and tension > lim.max_tension:
            reason = f'reel-in stopped: tension {tension:.1f} N > {lim.max_tension:g} N'
        if reason and not self.reason:
            self.trips += 1
        self.reason = reason
        return reason
