"""Spool drum with layered winding, and the motor encoder that measures the deployed length.

The prototype spools 100 m of 4.5 mm coaxial tether on a drum whose radius respects the
tether's 50 mm minimum bend radius (thesis Sec. 4.1, Fig. 4.1). The tether winds in layers
of ``n = floor(width/d)`` turns; the tether centre line of layer ``k`` (from 0 at the
drum) lies at ``r_k = r_core + d/2 + k d``, so one layer holds ``2π r_k n`` metres. Paying
out unwinds the outer layer first; the radius the tether leaves from, and with it the
length per spool turn, steps down by ``d`` every layer.

The spool angle ``θ`` counts from the start of a run, positive paying out, and maps one to
one onto the deployed length: within a layer ``dL = r_k dθ``. The motor encoder counts
``N θ`` in ``counts_per_rev`` steps per motor turn; the reel's firmware turns the count
back into a length through the same layer model, so the measured length is quantised to
``2π r_k/(N · counts_per_rev)``.

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 4.1.
"""

from __future__ import annotations

import bisect
import math


class SpoolGeometry:
    """Layered winding of ``capacity`` metres of tether on a drum.

    Parameters:
        core_radius: drum radius under the first layer (m).
        width: drum width between the flanges (m).
        tether_diameter: d (m).
        capacity: tether length on the spool when nothing is deployed (m).
        linear_density: tether mass per length (kg/m), for the wound tether's inertia.
    """

    def __init__(self, core_radius: float, width: float, tether_diameter: float, capacity: float,
                 linear_density: float) -> None:
        for name, value in (('core_radius', core_radius), ('width', width), ('tether_diameter', tether_diameter),
                            ('capacity', capacity), ('linear_density', linear_density)):
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'spool {name} must be a positive number, got {value}')
        if width < tether_diameter:
            raise ValueError(f'spool width {width} m is narrower than the tether diameter {tether_diameter} m')
        self.core_radius = core_radius
        self.tether_diameter = tether_diameter
        self.capacity = capacity
        self.linear_density = linear_density
        self.turns_per_layer = math.floor(width / tether_diameter)
        radii: list[float] = []
        lengths, angles, inertias = [0.0], [0.0], [0.0]
        while lengths[-1] < capacity:
            r = core_radius + tether_diameter * (0.5 + len(radii))
            layer = 2.0 * math.pi * r * self.turns_per_layer
            radii.append(r)
            lengths.append(lengths[-1] + layer)
            angles.append(angles[-1] + 2.0 * math.pi * self.turns_per_layer)
            inertias.append(inertias[-1] + linear_density * layer * r * r)
        self.layer_radius = radii
        self._wound_at = lengths
        self._angle_at = angles
        self._inertia_at = inertias

    @property
    def layers(self) -> int:
        """Number of layers the full capacity occupies."""
        return len(self.layer_radius)

    def _layer(self, wound: float) -> int:
        k = bisect.bisect_left(self._wound_at, wound) - 1
        return min(max(k, 0), self.layers - 1)

    def radius(self, deployed: float) -> float:
        """Radius (m) the tether leaves the drum from, with ``deployed`` metres paid out."""
        return self.layer_radius[self._layer(self.capacity - deployed)]

    def winding_angle(self, wound: float) -> float:
        """Drum angle (rad) that winds ``wound`` metres onto the empty drum."""
        k = self._layer(wound)
        return self._angle_at[k] + (wound - self._wound_at[k]) / self.layer_radius[k]

    def wound_length(self, angle: float) -> float:
        """Inverse of :meth:`winding_angle`: metres wound by ``angle`` (rad) from empty."""
        k = bisect.bisect_left(self._angle_at, angle) - 1
        k = min(max(k, 0), self.layers - 1)
        return self._wound_at[k] + (angle - self._angle_at[k]) * self.layer_radius[k]

    def deployed_length(self, initial_deployed: float, spool_angle: float) -> float:
        """Deployed length (m) after turning ``spool_angle`` (rad, + pays out) from ``initial_deployed``."""
        start = self.winding_angle(self.capacity - initial_deployed)
        return self.capacity - self.wound_length(start - spool_angle)

    def wound_inertia(self, deployed: float) -> float:
        """Moment of inertia (kg m²) of the tether still on the drum."""
        wound = self.capacity - deployed
        k = self._layer(wound)
        r = self.layer_radius[k]
        return self._inertia_at[k] + self.linear_density * (wound - self._wound_at[k]) * r * r


class Encoder:
    """Incremental motor encoder: counts of the spool angle through the gearbox.

    ``counts(θ) = floor(N θ cpr / 2π)``; :meth:`angle` turns a count back into the spool
    angle at the start of that count.
    """

    def __init__(self, counts_per_rev: int, gear_ratio: float) -> None:
        if counts_per_rev < 1:
            raise ValueError(f'encoder counts_per_rev must be at least 1, got {counts_per_rev}')
        self.counts_per_rev = counts_per_rev
        self.gear_ratio = gear_ratio
        self.step = 2.0 * math.pi / (counts_per_rev * gear_ratio)
        """Spool angle per count (rad)."""

    def counts(self, spool_angle: float) -> int:
        """Encoder count for the spool angle (rad)."""
        return math.floor(spool_angle / self.step + 1e-9)

    def angle(self, counts: int) -> float:
        """Spool angle (rad) of a count."""
        return counts * self.step
