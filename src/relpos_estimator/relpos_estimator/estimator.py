"""The relative-altitude estimator: Eq. 4.6-4.9 at 100 Hz with the dGPS message logic of Sec. 6.4.

:class:`Estimator` is stepped once per filter tick with the tick's accelerometer inputs and
the dGPS fixes that arrived since the previous tick (``step(t, a_reel, a_uav, fixes)``).
Each fix goes through the message logic, in this order, and is either fused or rejected
with one reason (:data:`REASONS`):

1. ``nonfinite``: a NaN or infinite position, time or reported sigma is a fault, never fused.
2. ``status``: below ``min_status`` (RTK fixed by default: the float fixes of a receiver
   that is recovering from a miss).
3. ``duplicate``: same sequence number and time of fix as a fix already received.
4. ``stale``: the receiver's clock did not advance with the local clock. The fix's age,
   arrival minus receiver time of fix, must lie in [-``clock_tolerance``, ``max_age``]; a
   fix whose time of fix is that of a fix already fused is stale. Equivalently the
   receiver-time delta between two fixes agrees with the local-clock delta up to the
   spread of ages the filter can absorb by retrodiction.
5. ``jump``: the altitude differs from the accepted fix nearest in receiver time by more
   than ``max_jump`` (1 m, Sec. 6.4) plus ``max_speed`` times the gap beyond one period, so
   that a genuine motion during a dropout does not lock the filter out.
6. ``innovation``: normalized innovation squared NIS = y^2 / S above ``gate_chi2``, the
   chi-square quantile of 1 degree of freedom (default 15.14, probability 0.9999), with
   S = min(P_zz, v, ``gate_max_std``^2) + s_fix^2. Convention: y is the fix minus the
   filter's altitude at the fix's own time of fix, before the fix; s_fix is the vertical
   1-sigma the receiver reports with the fix (not the tuned sigma_dGPS, a filter knob);
   v is the mean squared innovation of the accepted on-schedule fixes (running mean over
   the last 20). P_zz is capped so that the gate stays strict after a dropout, when P_zz -
   and with it the plain Mahalanobis gate - has grown (a gate alone let a 15 m spike move
   another filter by 4.5 m), and because the tuned Q (sigma_z = 0.0133 m^2 per step)
   makes P_zz far larger than the real prediction error. The gate is applied once
   ``reacquire_after`` on-schedule fixes were accepted (before, the filter is converging
   and only the jump test applies). With the defaults a fix more than 0.12 m off the
   prediction always fails.

Hold: a fix passed to :meth:`Estimator.step` is kept until the first tick at or after its
arrival plus ``fix_hold`` (0.02 s, two ticks) and considered then, in arrival order. The
hold makes a node's result independent of message timing: the sensors publish a fix two
lockstep rounds before the filter may use it, so it is in whatever the load; a fix that
still comes later is fused at its time of fix all the same (retrodiction, below). The
FOH baseline gets the fixes at the same tick as the filter.

Retrodiction: a fix is fused at its time of fix, rounded to the filter tick. The filter
keeps ``history`` seconds of posteriors, accelerometer inputs and fused fixes per tick;
a fix for an earlier tick restores that tick's state, is fused there, and the filter is
propagated again through the stored inputs (and the other fixes fused on the way) to
the present. A late or out-of-order fix thus gives the estimate it would have given on
time.

Weight: a fix is fused with R = max(sigma_dgps, s_fix^2), the receiver's own vertical
variance when it is worse than the tuned one, as the gate already weighs it.

If ``reacquire_after`` consecutive fixes are rejected by the jump or the innovation test
while agreeing among themselves (pairwise within the jump limit), the filter re-acquires
on them: its altitude is reset to the oldest of them still in the history, the altitude
rate's variance re-opened to its initial value, and the others fused in order (retrodiction),
so the rate is learnt again from the fixes as well as the altitude. A filter whose rate
drifted cannot lock itself out for good (a reset of the altitude alone left a 0.3-1.0 m/s
rate error that the gate locked in, re-acquired every 2 s, for 50 s of a flight).

The first-order hold (FOH) baseline of Sec. 6.2 extrapolates the line through the last
two accepted fixes; the horizontal relative position and radial distance pass through
from the latest accepted fix at the dGPS rate, unless it jumped (:meth:`Estimator._horizontal_plausible`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field
from typing import cast

import numpy as np

from relpos_estimator.kalman import Covariances
from relpos_estimator.kalman import RelativeAltitudeFilter
from tether_models.dgps import Fix
from tether_models.dgps import STATUS_RTK_FIXED

REASONS = {
    'nonfinite': 256,
    'status': 8,
    'duplicate': 64,
    'stale': 2,
    'too_old': 512,
    'jump': 4,
    'innovation': 128,
}
"""Rejection reasons and their RelativeEstimate.msg REJECT_* bits."""
REJECT_IMU_REEL = 16
REJECT_IMU_UAV = 32


@dataclass(frozen=True)
class LogicConfig:
    """Message-logic settings (SI units)."""

    min_status: int = STATUS_RTK_FIXED
    clock_tolerance: float = 0.02
    max_age: float = 1.0
    max_jump: float = 1.0
    max_speed: float = 2.0
    gate_chi2: float = 15.137
    gate_max_std: float = 0.03
    reacquire_after: int = 8
    history: float = 2.0
    fix_hold: float = 0.02


@dataclass
class Rejection:
    """A fix the logic refused, with the numbers behind the decision."""

    arrival: float
    fix_time: float
    sequence: int
    reason: str
    detail: str
    dz: float
    innovation: float = math.nan
    nis: float = math.nan

    @property
    def bit(self) -> int:
        """RelativeEstimate.msg REJECT_* bit of :attr:`reason`."""
        return REASONS[self.reason]


@dataclass
class Estimate:
    """Output of one filter tick."""

    t: float
    x: np.ndarray
    P: np.ndarray  # noqa: N815
    initialized: bool
    foh: float
    foh_rate: float
    horizontal: np.ndarray
    radial: float
    horizontal_fix_time: float
    rejected: int
    rejections: list[Rejection] = field(default_factory=list)
    fused: list[Fix] = field(default_factory=list)
    nis: float = math.nan


@dataclass
class _Tick:
    k: int
    x: np.ndarray
    P: np.ndarray  # noqa: N815
    imu: tuple[float | None, float | None]
    fixes: list[tuple[float, float]] = field(default_factory=list)
    """(altitude m, reported vertical variance m^2) of each fix fused at this tick."""


class FirstOrderHold:
    """Line through the last two accepted fixes, extrapolated (the thesis's FOH baseline, Sec. 6.2)."""

    def __init__(self) -> None:
        self.points: deque[tuple[float, float]] = deque(maxlen=2)

    def add(self, fix_time: float, dz: float) -> None:
        """Take an accepted fix; out-of-order fixes older than the newest are ignored."""
        if self.points and fix_time <= self.points[-1][0]:
            return
        self.points.append((fix_time, dz))

    def value(self, t: float) -> tuple[float, float]:
        """Altitude (m) and slope (m/s) at ``t``; NaN before the first fix."""
        if not self.points:
            return math.nan, math.nan
        t1, z1 = self.points[-1]
        if len(self.points) == 1:
            return z1, 0.0
        t0, z0 = self.points[0]
        slope = (z1 - z0) / (t1 - t0)
        return z1 + slope * (t - t1), slope


class Estimator:
    """Filter, message logic, retrodiction and FOH, stepped per tick without ROS.

    Args:
        covariances: Q and R entries (thesis Sec. 6.2 by default).
        logic: message-logic settings.
        rate: Hz, filter rate (100 in the thesis).
        fix_period: s between dGPS epochs (0.25 at 4 Hz).
    """

    def __init__(self, covariances: Covariances = Covariances(), logic: LogicConfig = LogicConfig(),
                 rate: float = 100.0, fix_period: float = 0.25) -> None:
        self.dt = 1.0 / rate
        self.logic = logic
        self.fix_period = fix_period
        self.initial_variance = np.array([covariances.sigma_dgps, 1.0, 1.0, 1.0, 1.0])
        self.filter = RelativeAltitudeFilter(covariances, self.dt, self.initial_variance)
        self.history: deque[_Tick] = deque(maxlen=max(2, int(round(logic.history * rate)) + 1))
        self.k: int | None = None
        self.initialized = False
        self.accepted: dict[float, float] = {}
        self.received: set[tuple[int, float]] = set()
        self.foh = FirstOrderHold()
        self.horizontal = np.full(3, np.nan)
        self.horizontal_fix_time = math.nan
        self.suspects: list[Fix] = []
        self.regular_fixes = 0
        self.innovation_var = math.inf
        self.held: list[Fix] = []

    def tick_of(self, t: float) -> int:
        """Filter tick index of time ``t`` (s)."""
        return int(round(t / self.dt))

    def step(self, t: float, a_reel: float | None, a_uav: float | None, fixes: Sequence[Fix] = ()) -> Estimate:
        """Advance to tick ``t``, fuse the IMU inputs and the fixes due; return the estimate.

        ``a_reel``, ``a_uav``: world-vertical accelerations (m/s^2, gravity removed) of the
        reel and UAV IMUs at ``t``; None or NaN for a missing or faulty sample. ``fixes``:
        the fixes received since the previous step; each is considered at the first tick at
        or after its arrival plus ``fix_hold``.
        """
        k = self.tick_of(t)
        rejected = 0
        if a_reel is not None and not math.isfinite(a_reel):
            a_reel, rejected = None, rejected | REJECT_IMU_REEL
        if a_uav is not None and not math.isfinite(a_uav):
            a_uav, rejected = None, rejected | REJECT_IMU_UAV
        y1 = -a_reel if a_reel is not None else None
        y2 = a_uav - a_reel if a_reel is not None and a_uav is not None else None
        if self.k is not None:
            for _ in range(self.k + 1, k):
                self.filter.predict()
                self._record(self.history[-1].k + 1, (None, None))
            self.filter.predict()
        self.filter.update_imu(y1, y2)
        self.k = k
        self._record(k, (y1, y2))
        rejections: list[Rejection] = []
        fused: list[Fix] = []
        nis = math.nan
        self.held.extend(fixes)
        due = sorted((f for f in self.held if f.arrival + self.logic.fix_hold <= t + 1e-9),
                     key=lambda f: (f.arrival, f.sequence))
        self.held = [f for f in self.held if f.arrival + self.logic.fix_hold > t + 1e-9]
        for fix in due:
            outcome = self._consider(fix)
            if isinstance(outcome, Rejection):
                rejections.append(outcome)
                rejected |= outcome.bit
            else:
                fused.append(fix)
                nis = outcome
        foh, foh_rate = self.foh.value(t)
        return Estimate(t, self.filter.x.copy(), self.filter.P.copy(), self.initialized, foh, foh_rate,
                        self.horizontal.copy(), float(np.hypot(self.horizontal[0], self.horizontal[1])),
                        self.horizontal_fix_time, rejected, rejections, fused, nis)

    def _record(self, k: int, imu: tuple[float | None, float | None]) -> None:
        self.history.append(_Tick(k, self.filter.x.copy(), self.filter.P.copy(), imu))

    def _reject(self, fix: Fix, reason: str, detail: str, innovation: float = math.nan,
                nis: float = math.nan) -> Rejection:
        return Rejection(fix.arrival, fix.fix_time, fix.sequence, reason, detail, float(fix.position[2]),
                         innovation, nis)

    def _consider(self, fix: Fix) -> Rejection | float:
        """Run the message logic on one fix; fuse it and return its NIS, or return the rejection."""
        lg = self.logic
        values = np.concatenate([fix.position, fix.std, [fix.arrival, fix.fix_time]])
        if not np.all(np.isfinite(values)):
            return self._reject(fix, 'nonfinite', 'position, sigma or time not finite')
        if fix.status < lg.min_status:
            return self._reject(fix, 'status', f'status {fix.status} below {lg.min_status}')
        key = (fix.sequence, fix.fix_time)
        if key in self.received:
            return self._reject(fix, 'duplicate', f'sequence {fix.sequence} at {fix.fix_time:.3f} s received before')
        self.received.add(key)
        age = fix.arrival - fix.fix_time
        if age < -lg.clock_tolerance or age > lg.max_age:
            return self._reject(fix, 'stale', f'receiver time {fix.fix_time:.3f} s is {age:.3f} s behind the '
                                              f'local clock (allowed {-lg.clock_tolerance:g}..{lg.max_age:g})')
        j = self.tick_of(fix.fix_time)
        if fix.fix_time in self.accepted:
            return self._reject(fix, 'stale', f'receiver time {fix.fix_time:.3f} s did not advance past a fused fix')
        if j < self.history[0].k:
            return self._reject(fix, 'too_old', f'time of fix {fix.fix_time:.3f} s is before the '
                                                f'{lg.history:g} s history')
        j = min(j, cast(int, self.k))
        dz = float(fix.position[2])
        if not self.initialized:
            self._fuse_at(j, fix, reset=True)
            self.initialized = True
            return math.nan
        nearest = min(self.accepted, key=lambda tau: abs(tau - fix.fix_time))
        gap = abs(nearest - fix.fix_time)
        limit = self._jump_limit(gap)
        tick = self.history[j - self.history[0].k]
        innovation = dz - float(tick.x[0])
        s = min(float(tick.P[0, 0]), self.innovation_var, lg.gate_max_std**2) + float(fix.std[2]) ** 2
        nis = innovation**2 / s
        gated = self.regular_fixes >= lg.reacquire_after and nis > lg.gate_chi2
        jump = abs(dz - self.accepted[nearest])
        if jump > limit or gated:
            suspects = self._reacquire(fix, limit)
            if suspects:
                self._reacquire_on(suspects)
                return nis
            if jump > limit:
                return self._reject(fix, 'jump', f'{jump:.3f} m from the fix at {nearest:.3f} s '
                                                 f'(limit {limit:.3f} m)', innovation, nis)
            return self._reject(fix, 'innovation', f'NIS {nis:.1f} > {lg.gate_chi2:g} '
                                                   f'(innovation {innovation:.3f} m)', innovation, nis)
        self.suspects.clear()
        if gap <= 1.5 * self.fix_period:
            self.regular_fixes += 1
            weight = 1.0 / min(self.regular_fixes, 20)
            self.innovation_var += weight * (innovation**2 - self.innovation_var) if self.regular_fixes > 1 else 0.0
            if self.regular_fixes == 1:
                self.innovation_var = innovation**2
        self._fuse_at(j, fix, reset=False)
        return nis

    def _reacquire(self, fix: Fix, limit: float) -> list[Fix]:
        """Count a suspect fix; once enough mutually consistent suspects say the filter is wrong, return
        them (the filter re-acquires on them), else an empty list.
        """
        self.suspects.append(fix)
        if len(self.suspects) < self.logic.reacquire_after:
            return []
        recent = self.suspects[-self.logic.reacquire_after:]
        if not all(abs(b.position[2] - a.position[2]) <= limit for a, b in zip(recent, recent[1:])):
            return []
        self.suspects.clear()
        return recent

    def _reacquire_on(self, suspects: list[Fix]) -> None:
        """Reset the altitude to the oldest suspect in the history with the rate's variance re-opened,
        then fuse the others in order of time of fix.
        """
        first = self.history[0].k
        usable = sorted((f for f in suspects if self.tick_of(f.fix_time) >= first), key=lambda f: f.fix_time)
        if not usable:
            usable = [suspects[-1]]
        newest = cast(int, self.k)
        for n, fix in enumerate(usable):
            self._fuse_at(min(max(self.tick_of(fix.fix_time), first), newest), fix, reset=n == 0, rate_reset=True)

    def _fuse_at(self, j: int, fix: Fix, reset: bool, rate_reset: bool = False) -> None:
        """Fuse ``fix`` at tick ``j`` and propagate again to the present (retrodiction).

        ``reset``: the altitude is set to the fix instead (its variance to sigma_dgps), and with
        ``rate_reset`` the altitude rate's variance to its initial value, uncorrelated.
        """
        first = self.history[0].k
        start = j - first
        tick = self.history[start]
        dz, variance = float(fix.position[2]), float(fix.std[2]) ** 2
        x, P = tick.x.copy(), tick.P.copy()  # noqa: N806
        if reset:
            for i in (0, 1) if rate_reset else (0,):
                P[i, :] = 0.0
                P[:, i] = 0.0
                P[i, i] = self.initial_variance[i]
            x[0] = dz
        self.filter.restore(x, P)
        tick.fixes.append((dz, variance))
        if not reset:
            self.filter.update_dgps(dz, variance)
        tick.x, tick.P = self.filter.x.copy(), self.filter.P.copy()
        for tick in list(self.history)[start + 1:]:
            self.filter.predict()
            self.filter.update_imu(*tick.imu)
            for value, fix_variance in tick.fixes:
                self.filter.update_dgps(value, fix_variance)
            tick.x, tick.P = self.filter.x.copy(), self.filter.P.copy()
        self.accepted[fix.fix_time] = dz
        self._forget_old_fixes()
        self.foh.add(fix.fix_time, dz)
        if not fix.fix_time < self.horizontal_fix_time and self._horizontal_plausible(fix):
            self.horizontal = np.array([fix.position[0], fix.position[1], 0.0])
            self.horizontal_fix_time = fix.fix_time

    def _horizontal_plausible(self, fix: Fix) -> bool:
        """The jump test of the altitude (Sec. 6.4) on the horizontal: a fused fix passes its x, y
        through unless they lie further from the last ones passed than ``max_jump`` plus ``max_speed``
        times the gap beyond one period (a fix whose altitude agrees can be metres off horizontally,
        and the reel's reference would follow it).
        """
        if not math.isfinite(self.horizontal_fix_time):
            return True
        limit = self._jump_limit(fix.fix_time - self.horizontal_fix_time)
        return math.hypot(fix.position[0] - self.horizontal[0], fix.position[1] - self.horizontal[1]) <= limit

    def _jump_limit(self, gap: float) -> float:
        """Largest plausible change (m) between fixes ``gap`` s apart: ``max_jump`` plus ``max_speed``
        times the gap beyond one period (Sec. 6.4).
        """
        return self.logic.max_jump + self.logic.max_speed * max(0.0, gap - self.fix_period)

    def _forget_old_fixes(self) -> None:
        horizon = (self.history[0].k - 1) * self.dt - self.logic.max_age
        for tau in [tau for tau in self.accepted if tau < horizon]:
            if len(self.accepted) > 1:
                del self.accepted[tau]
        self.received = {key for key in self.received if key[1] >= horizon}
