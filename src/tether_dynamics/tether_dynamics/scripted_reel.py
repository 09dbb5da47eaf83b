"""A scripted reel: the deployed length follows the catenary reference from ground truth.

Until the smart reel (its own package, thesis Sec. 4.2) closes the loop over its sensors and
motor, a scene can let the plant's spool follow the heave-robust reference length of the
true relative position directly (Eq. 4.4/4.5 with the safeguards of
:mod:`tether_dynamics.statics.reference_length`): the payout rate is the reference's rate of change
plus a proportional correction of the length error,

    v = (L_ref(t_k) - L_ref(t_k-1)) / (t_k - t_k-1) + k (L_ref(t_k) - L),

computed from the relative position of the plant's previous output step (an explicit
one-step delay). There is no filter, motor or sensor: it is the ideal the smart reel is
measured against, not a model of it.
"""

from __future__ import annotations

import math

from tether_dynamics.statics.reference_length import reference_length


class ScriptedReel:
    """Payout rate that makes the deployed length follow the reference length.

    Args:
        gain: proportional gain k on the length error (1/s).
    """

    def __init__(self, gain: float) -> None:
        if not gain >= 0.0:
            raise ValueError(f'reference gain must be >= 0, got {gain}')
        self.gain = gain
        self._last: tuple[float, float] | None = None
        self.reference = math.nan

    def step(self, t: float, relative_position: tuple[float, float, float], deployed_length: float) -> float:
        """Return the payout rate (m/s, + pays out) for the relative position seen at time ``t`` (s).

        ``relative_position`` is UAV attachment minus guide way in world (m); the first call
        has no rate of change and returns the proportional term only.
        """
        dx, dy, dz = relative_position
        self.reference = reference_length(math.hypot(dx, dy), dz).length
        rate = 0.0
        if self._last is not None and t > self._last[0]:
            rate = (self.reference - self._last[1]) / (t - self._last[0])
        self._last = (t, self.reference)
        return rate + self.gain * (self.reference - deployed_length)
