"""Safety trips of the smart reel (thesis Ch. 4: "safety precautions to prevent catastrophic forces").

Paying out is stopped when the tether's lowest point comes within ``min_clearance`` of the
deck or the water, or when the guide arm reads a departure angle below
``min_departure_angle`` (the tether leaving the reel downward, towards the deck); reeling
in is stopped when the tension estimate exceeds ``max_tension``. A trip brakes the reel for
as long as the controller asks for the blocked direction and the condition lasts; each trip
has a reason, and every rising edge is counted.

A condition trips only once it has lasted ``trip_delay`` (0.1 s, five controller ticks at
50 Hz), or at once when it passes its limit by the hard band. The guide arm's reading is
the departure angle plus or minus half its follower's 20 degree dead band, the side
switching when the payout reverses (Sec. 6.1.3), so one reading can jump by 10-20 degrees
within a tick with no change of the tether; and the plant's departure angle is the tangent
of its first element, which swings as the moving reel splits and merges elements (a 0.1 s
swing of 25 degrees and back at a merge in the default scene). A reading must therefore
stay past the limit for several ticks, or pass it by half the dead band (the follower's
offset), to mean the tether really leaves downward. A tripped reel recovers once the
condition is back inside its limit by the release band (hysteresis, so that a reading
at the limit does not toggle the brake every tick), or once the controller asks for the
other direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SafetyLimits:
    """Trip thresholds, their hard and release bands, and the persistence a trip needs."""

    min_clearance: float = 0.2
    """m, lowest point above the deck or the water."""
    min_departure_angle: float = -0.35
    """rad, guide-arm reading."""
    max_tension: float = 80.0
    """N, tension estimate while reeling in."""
    trip_delay: float = 0.1
    """s, how long a condition must last before it trips (0: at once)."""
    hard_angle: float = math.radians(10.0)
    """rad, a reading this far below the limit trips at once (half the guide arm's dead band)."""
    hard_tension: float = 20.0
    """N, a tension this far above the limit trips at once."""
    release_angle: float = math.radians(2.0)
    """rad, a trip on the angle holds until the reading is this far above the limit."""
    release_clearance: float = 0.05
    """m, a trip on the clearance holds until the lowest point is this far above the limit."""
    release_tension: float = 5.0
    """N, a trip on the tension holds until the estimate is this far below the limit."""


class SafetyMonitor:
    """Checks a commanded direction against the limits at stamped ticks; remembers the trip count."""

    def __init__(self, limits: SafetyLimits) -> None:
        self.limits = limits
        self.reason = ''
        self.trips = 0
        self._pending: tuple[str, float] | None = None    # (condition, time it started)

    def _condition(self, direction: float, clearance: float, arm_angle: float,
                   tension: float) -> tuple[str, str, bool]:
        """(condition, reason, hard) of the limit the command would pass; while tripped, the limit moved
        inward by the release band.
        """
        lim = self.limits
        held = self.reason != ''
        if direction > 0.0:
            floor = lim.min_clearance + (lim.release_clearance if held else 0.0)
            if math.isfinite(clearance) and clearance < floor:
                return ('clearance', f'payout stopped: lowest point {clearance:.3f} m above deck/water < {floor:g} m',
                        clearance <= 0.0)
            floor = lim.min_departure_angle + (lim.release_angle if held else 0.0)
            if math.isfinite(arm_angle) and arm_angle < floor:
                return ('angle', f'payout stopped: departure angle {math.degrees(arm_angle):.1f} deg < '
                        f'{math.degrees(floor):g} deg', arm_angle < lim.min_departure_angle - lim.hard_angle)
        elif direction < 0.0:
            ceiling = lim.max_tension - (lim.release_tension if held else 0.0)
            if tension > ceiling:
                return ('tension', f'reel-in stopped: tension {tension:.1f} N > {ceiling:g} N',
                        tension > lim.max_tension + lim.hard_tension)
        return '', '', False

    def check(self, t: float, direction: float, clearance: float, arm_angle: float, tension: float) -> str:
        """Return the trip reason at tick ``t`` (s) for a command of sign ``direction`` (+ pays out), or ''.

        The reason is the one of the tick that tripped, kept while the trip holds on the same condition.
        """
        condition, reason, hard = self._condition(direction, clearance, arm_angle, tension)
        if not condition:
            self._pending = None
            self.reason = ''
            return ''
        if self._pending is None or self._pending[0] != condition:
            self._pending = (condition, t)
            if self.reason:
                self.reason = reason
        lasted = t - self._pending[1]
        if not self.reason and (hard or lasted >= self.limits.trip_delay - 1e-9):
            self.trips += 1
            self.reason = reason if hard or lasted <= 0.0 else f'{reason} for {lasted:.2f} s'
        return self.reason
