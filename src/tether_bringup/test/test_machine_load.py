"""machine_load: the cores' time between two /proc/stat readings, split into this run, other processes, idle, stolen."""

from __future__ import annotations

import pytest

from tether_bringup.machine_load import core_times
from tether_bringup.machine_load import parse_stat
from tether_bringup.machine_load import shares

# proc(5): cpu user nice system idle iowait irq softirq steal guest guest_nice (clock ticks)
BEFORE = 'cpu  1000 10 200 5000 40 0 50 100 30 0\ncpu0 500 5 100 2500 20 0 25 50 15 0\n'
AFTER = 'cpu  1300 10 260 5100 60 0 60 220 90 0\ncpu0 650 5 130 2550 30 0 30 110 45 0\n'


def test_parse_stat_reads_the_aggregate_line_in_seconds():
    times = parse_stat(BEFORE, 100.0)
    assert times.total == pytest.approx(64.0)       # guest time is part of user, not added again
    assert times.idle == pytest.approx(50.4)        # idle and I/O wait
    assert times.steal == pytest.approx(1.0)
    assert times.busy == pytest.approx(12.6)
    assert parse_stat('intr 1 2 3\n', 100.0) is None


def test_shares_split_the_interval_and_add_up_to_one():
    start, end = parse_stat(BEFORE, 100.0), parse_stat(AFTER, 100.0)
    # 610 ticks in all: 370 busy, 120 idle, 120 stolen; this run used 2.5 s of the 3.7 s busy
    split = shares(start, end, 2.5)
    assert split == pytest.approx({'this run': 2.5 / 6.1, 'other processes': 1.2 / 6.1, 'idle': 1.2 / 6.1,
                                   'stolen by the hypervisor': 1.2 / 6.1})
    assert shares(start, end, 10.0)['other processes'] == 0.0  # the run's CPU, rounded up, cannot exceed the busy time
    assert shares(start, start, 1.0) is None


def test_this_machine_has_a_stat_line():
    times = core_times()
    assert times is not None and times.total > 0 and times.busy + times.idle + times.steal == pytest.approx(times.total)
