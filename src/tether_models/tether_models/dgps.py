"""RTK dGPS relative-position receiver with the faults seen outdoors (thesis Sec. 5.4, 6.4, Table 5.1).

A u-blox NEO-M8P-2 pair (base on the boat, rover on the UAV) outputs the rover-minus-base
position at 4 Hz. Each epoch's fix is taken at the receiver's time of fix ``fix_time`` (an
exact multiple of the period on the sim time axis) and arrives at the reel computer
``latency`` later, with Gaussian jitter. Faults (Sec. 6.4), each with its own rate:

* ``missed``: no message for the epoch (1.35 % of messages outdoors);
* ``stale``: the message following a miss often repeats the previous output, its position
  and its time of fix (the receiver's clock did not advance with the local clock);
* ``recovering``: for ``recovery_time`` after a miss the receiver "sorts itself out": its
  fixes are RTK float with ``recovery_noise``;
* ``wild``: a completely wrong fix, reported as RTK fixed, off by ``wild_min``..``wild_max``
  metres in a random direction;
* ``late``: a message delayed by an extra ``late_delay``, arriving after the next one;
* ``duplicate``: the same message delivered twice;
* ``nonfinite``: a NaN in the vertical component.

Every epoch draws the same random numbers in the same order whatever happens, so turning
one fault on or off does not change the noise of the others: 7 uniforms (miss, stale, wild,
late, duplicate, nonfinite, wild magnitude), 3 normals of position noise, 1 of latency
jitter and 3 of the wild direction.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field

import numpy as np

STATUS_NO_FIX = 0
STATUS_SINGLE = 1
STATUS_DGPS = 2
STATUS_RTK_FLOAT = 3
STATUS_RTK_FIXED = 4
"""DgpsFix.msg status values."""

FAULT_KINDS = ('missed', 'stale', 'recovering', 'wild', 'late', 'duplicate', 'nonfinite')


@dataclass(frozen=True)
class DgpsConfig:
    """Receiver figures and fault rates (SI units; rates are probabilities per epoch)."""

    rate: float = 4.0
    noise_std: tuple[float, float, float] = (0.01, 0.01, 0.01)
    latency: float = 0.05
    latency_jitter: float = 0.01
    min_latency: float = 0.005
    miss_rate: float = 0.0135
    stale_after_miss: float = 0.6
    recovery_time: float = 1.0
    recovery_noise: float = 0.3
    wild_rate: float = 0.002
    wild_min: float = 0.5
    wild_max: float = 20.0
    late_rate: float = 0.0
    late_delay: float = 0.4
    duplicate_rate: float = 0.0
    nonfinite_rate: float = 0.0


@dataclass
class Fix:
    """One dGPS message as the reel computer receives it."""

    arrival: float
    """s, sim time of arrival (the message's header stamp)."""
    fix_time: float
    """s, receiver's time of fix."""
    position: np.ndarray
    """m, rover minus base, ENU."""
    std: np.ndarray
    """m, 1-sigma the receiver reports, per axis."""
    status: int
    sequence: int


@dataclass
class Fault:
    """One injected fault and its ground truth."""

    kind: str
    time: float
    """s, when it shows: the faulty message's arrival, or the due time of a missed one."""
    fix_time: float
    """s, the epoch it belongs to."""
    sequence: int
    truth: np.ndarray
    """m, true relative position at ``fix_time``."""
    reported: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))
    """m, what the message said (NaN for a missed message)."""


class DgpsReceiver:
    """Epoch-by-epoch receiver model; :meth:`epoch` returns the messages and faults of one epoch."""

    def __init__(self, config: DgpsConfig, rng: np.random.Generator) -> None:
        self.config = config
        self.rng = rng
        self.sequence = 0
        self.recovery_end = -np.inf
        self.stale_pending = False
        self.last: Fix | None = None

    @property
    def period(self) -> float:
        """s between epochs."""
        return 1.0 / self.config.rate

    def epoch(self, fix_time: float, truth: np.ndarray) -> tuple[list[Fix], list[Fault]]:
        """Messages (in arrival order) and faults of the epoch at ``fix_time`` with true position ``truth`` (m)."""
        c = self.config
        rng = self.rng
        u = rng.random(7)
        noise = rng.normal(0.0, 1.0, 3)
        jitter = rng.normal(0.0, 1.0)
        direction = rng.normal(0.0, 1.0, 3)
        truth = np.asarray(truth, dtype=float)
        self.sequence += 1
        latency = max(c.min_latency, c.latency + c.latency_jitter * jitter)
        arrival = fix_time + latency
        std = np.asarray(c.noise_std, dtype=float)
        faults: list[Fault] = []
        recovering = fix_time < self.recovery_end
        if not recovering and u[0] < c.miss_rate:
            self.recovery_end = fix_time + c.recovery_time
            self.stale_pending = u[1] < c.stale_after_miss
            return [], [Fault('missed', fix_time + c.latency, fix_time, self.sequence, truth)]
        if recovering and self.stale_pending and self.last is not None:
            self.stale_pending = False
            old = self.last
            fix = Fix(arrival, old.fix_time, old.position.copy(), old.std.copy(), old.status, self.sequence)
            faults.append(Fault('stale', arrival, fix_time, self.sequence, truth, fix.position.copy()))
        elif recovering:
            std = np.full(3, c.recovery_noise)
            fix = Fix(arrival, fix_time, truth + std * noise, std, STATUS_RTK_FLOAT, self.sequence)
            faults.append(Fault('recovering', arrival, fix_time, self.sequence, truth, fix.position.copy()))
        else:
            fix = Fix(arrival, fix_time, truth + std * noise, std, STATUS_RTK_FIXED, self.sequence)
        if u[2] < c.wild_rate:
            magnitude = c.wild_min + (c.wild_max - c.wild_min) * u[6]
            fix.position = truth + magnitude * direction / np.linalg.norm(direction)
            fix.status = STATUS_RTK_FIXED
            faults.append(Fault('wild', arrival, fix_time, self.sequence, truth, fix.position.copy()))
        self.last = Fix(fix.arrival, fix.fix_time, fix.position.copy(), fix.std.copy(), fix.status, fix.sequence)
        if u[3] < c.late_rate:
            fix.arrival += c.late_delay
            faults.append(Fault('late', fix.arrival, fix_time, self.sequence, truth, fix.position.copy()))
        if u[5] < c.nonfinite_rate:
            fix.position[2] = np.nan
            faults.append(Fault('nonfinite', fix.arrival, fix_time, self.sequence, truth, fix.position.copy()))
        messages = [fix]
        if u[4] < c.duplicate_rate:
            copy = Fix(fix.arrival + 0.01, fix.fix_time, fix.position.copy(), fix.std.copy(), fix.status,
                       fix.sequence)
            messages.append(copy)
            faults.append(Fault('duplicate', copy.arrival, fix_time, self.sequence, truth, copy.position.copy()))
        return messages, faults
