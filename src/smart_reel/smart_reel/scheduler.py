"""The reference length's low-pass filter and its gain schedule (thesis Sec. 4.2, 6.2).

Eq. 4.1, a first-order discrete low-pass filter on the reference length:

    L^LP_k = (1 - α) L^LP_{k-1} + α L_ref,k

α = 1 passes the reference through; α = 0.2 smooths it while the relative vertical velocity
is low, where the estimate of the relative altitude is least smooth (Sec. 6.2).

The schedule works like a Schmitt trigger (Sec. 4.2): the filter turns on when the speed
``|Δż|`` falls below the threshold, normally 0.3 m/s; once the speed has fallen below
0.1 m/s the threshold itself drops to 0.1 m/s, so the filter turns off as soon as the
speed rises past 0.1 m/s ("abruptly turning off the filter with increasing relative
velocity") and turns on again at 0.1 m/s as long as the speed has not been above 0.3 m/s
(Sec. 6.2: "the lower magnitude threshold activates if the relative velocity has not gone
above the higher magnitude threshold"). Above 0.3 m/s the threshold returns to 0.3 m/s.
Between 0.1 and 0.3 m/s the state therefore depends on the history: the hysteresis.
"""

from __future__ import annotations


class SchmittScheduler:
    """Two-threshold schedule of the filter coefficient α on the relative vertical speed."""

    def __init__(self, upper: float = 0.3, lower: float = 0.1, alpha_slow: float = 0.2) -> None:
        if not 0.0 <= lower <= upper:
            raise ValueError(f'scheduler thresholds need 0 <= lower <= upper, got {lower}, {upper}')
        if not 0.0 < alpha_slow <= 1.0:
            raise ValueError(f'alpha_slow must be in (0, 1], got {alpha_slow}')
        self.upper = upper
        self.lower = lower
        self.alpha_slow = alpha_slow
        self.threshold = upper
        self.slow = False

    def update(self, vertical_velocity: float) -> float:
        """Advance the schedule with the relative vertical velocity (m/s); return α."""
        speed = abs(vertical_velocity)
        if speed < self.lower:
            self.threshold = self.lower
        elif speed > self.upper:
            self.threshold = self.upper
        self.slow = speed < self.threshold
        return self.alpha_slow if self.slow else 1.0


class LowPass:
    """Eq. 4.1; the first sample initialises the output."""

    def __init__(self) -> None:
        self.value: float | None = None

    def update(self, sample: float, alpha: float) -> float:
        """Filter one sample with coefficient ``alpha`` (1 passes it through)."""
        self.value = sample if self.value is None else (1.0 - alpha) * self.value + alpha * sample
        return self.value
