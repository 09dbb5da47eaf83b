"""Pacing of simulated time against wall time at a requested real-time factor."""

from __future__ import annotations

import math
import time

MAX_RATE = math.inf


def rate_text(rate: float) -> str:
    """A real-time factor as scenes and the command line write it (``max`` for no pacing)."""
    return 'max' if math.isinf(rate) else f'{rate:g}'


class SimClock:
    """Advance sim time in fixed steps, each released when the wall clock allows.

    Tick ``k`` carries sim time ``k * step`` and is due at wall time
    ``start + k * step / rate``. When the publisher falls behind, ticks are released
    immediately until it has caught up, so the achieved rate never exceeds the request.
    ``rate`` = :data:`MAX_RATE` releases every tick at once (the lockstep barrier paces).
    """

    def __init__(self, step: float, rate: float) -> None:
        if step <= 0 or rate <= 0:
            raise ValueError('step and rate must be positive')
        self.step = step
        self.rate = rate
        self.ticks = 0
        self.wall_start: float | None = None
        self.wall_stop: float | None = None

    @property
    def sim_time(self) -> float:
        """Sim time of the latest tick, s."""
        return self.ticks * self.step

    def next_tick(self) -> float:
        """Sleep until the next tick is due, advance, and return its sim time."""
        now = time.monotonic()
        if self.wall_start is None:
            self.wall_start = now
        self.ticks += 1
        due = self.wall_start + self.ticks * self.step / self.rate
        if due > now:
            time.sleep(due - now)
        return self.sim_time

    def stop(self) -> None:
        """Freeze the wall time used by :meth:`achieved_rate` (the run has ended)."""
        if self.wall_stop is None:
            self.wall_stop = time.monotonic()

    def achieved_rate(self) -> float:
        """Sim time elapsed per wall second between the first tick and the stop (or now)."""
        if self.wall_start is None:
            return 0.0
        elapsed = (self.wall_stop or time.monotonic()) - self.wall_start
        return self.sim_time / elapsed if elapsed > 0 else 0.0
