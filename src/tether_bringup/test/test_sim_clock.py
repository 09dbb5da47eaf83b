"""SimClock: sim time advances by whole steps and never runs ahead of the requested rate."""

from __future__ import annotations

import time

import pytest

from tether_bringup.sim_clock import MAX_RATE
from tether_bringup.sim_clock import SimClock
from tether_bringup.sim_clock import rate_text


def test_ticks_advance_in_steps():
    clock = SimClock(step=0.01, rate=1000.0)
    times = [clock.next_tick() for _ in range(5)]
    assert times == pytest.approx([0.01, 0.02, 0.03, 0.04, 0.05])


def test_achieved_rate_does_not_exceed_request():
    clock = SimClock(step=0.01, rate=5.0)
    start = time.monotonic()
    for _ in range(20):
        clock.next_tick()
    clock.stop()
    assert time.monotonic() - start >= 0.19 * 0.2 * 5 / 5
    assert clock.achieved_rate() <= 5.0 * 1.0001


def test_rejects_non_positive_settings():
    with pytest.raises(ValueError):
        SimClock(step=0.0, rate=1.0)


def test_max_rate_releases_ticks_at_once(monkeypatch):
    slept = []
    monkeypatch.setattr(time, 'sleep', slept.append)
    clock = SimClock(step=1.0, rate=MAX_RATE)
    for _ in range(100):
        clock.next_tick()
    assert clock.sim_time == 100.0 and slept == []
    assert rate_text(MAX_RATE) == 'max' and rate_text(20.0) == '20'
