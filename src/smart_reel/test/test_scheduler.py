"""Schmitt-trigger schedule of Eq. 4.1's filter coefficient on constructed velocity traces."""

from __future__ import annotations

import pytest

from smart_reel.scheduler import LowPass
from smart_reel.scheduler import SchmittScheduler


def run(trace):
    s = SchmittScheduler(0.3, 0.1, 0.2)
    return [s.update(v) for v in trace]


def test_filter_turns_on_below_the_upper_threshold_when_slowing_down():
    assert run([0.5, 0.35, 0.31, 0.29, 0.2]) == [1.0, 1.0, 1.0, 0.2, 0.2]
    assert run([-0.5, -0.29]) == [1.0, 0.2]  # on the speed |dz_rate|


def test_without_dipping_below_the_lower_threshold_it_stays_on_until_above_the_upper():
    # 0.29 -> on; rising through 0.2, 0.29 keeps it on (threshold still 0.3); above 0.3 off
    assert run([0.5, 0.29, 0.2, 0.29, 0.31]) == [1.0, 0.2, 0.2, 0.2, 1.0]


def test_after_dipping_below_the_lower_threshold_it_turns_off_above_it():
    assert run([0.5, 0.2, 0.05, 0.11, 0.2]) == [1.0, 0.2, 0.2, 1.0, 1.0]


def test_lower_threshold_stays_until_the_speed_exceeds_the_upper_one():
    # after 0.05 the threshold is 0.1: 0.2 off, 0.15 off, 0.09 on again (lower threshold),
    # 0.35 off and the threshold back at 0.3, 0.25 on
    trace = [0.5, 0.05, 0.2, 0.15, 0.09, 0.35, 0.25]
    assert run(trace) == [1.0, 0.2, 1.0, 1.0, 0.2, 1.0, 0.2]


def test_hysteresis_same_speed_two_states():
    a = SchmittScheduler()
    b = SchmittScheduler()
    for v in (0.5, 0.05, 0.2):
        a.update(v)
    for v in (0.5, 0.25, 0.2):
        b.update(v)
    assert a.slow is False and b.slow is True


def test_low_pass_is_eq_4_1():
    f = LowPass()
    assert f.update(1.0, 0.2) == 1.0
    values = [f.update(0.0, 0.2) for _ in range(5)]
    assert values == pytest.approx([0.8**k for k in range(1, 6)])
    assert f.update(3.0, 1.0) == 3.0


def test_bad_thresholds_are_refused():
    with pytest.raises(ValueError, match='thresholds'):
        SchmittScheduler(0.1, 0.3)
