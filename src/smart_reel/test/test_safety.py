"""Safety trips: direction-gated, counted, and the reel holds."""

from __future__ import annotations

import math

from smart_reel.reel import ReelInputs
from smart_reel.reel import build_core
from smart_reel.safety import SafetyLimits
from smart_reel.safety import SafetyMonitor
from smart_reel.tuning import default_parameters

LIMITS = SafetyLimits(min_clearance=0.2, min_departure_angle=0.0, max_tension=80.0)


def test_clearance_and_departure_angle_block_only_payout():
    s = SafetyMonitor(LIMITS)
    assert 'lowest point' in s.check(+1.0, 0.1, 0.5, 1.0)
    assert s.check(-1.0, 0.1, 0.5, 1.0) == ''
    assert 'departure angle' in s.check(+1.0, 1.0, math.radians(-2.0), 1.0)
    assert s.check(+1.0, 1.0, math.radians(5.0), 1.0) == ''


def test_tension_blocks_only_reel_in_and_trips_are_counted_once_per_event():
    s = SafetyMonitor(LIMITS)
    assert 'tension 90.0 N' in s.check(-1.0, math.inf, 0.5, 90.0)
    assert s.check(-1.0, math.inf, 0.5, 95.0)
    assert s.trips == 1
    assert s.check(+1.0, math.inf, 0.5, 95.0) == ''
    assert s.check(-1.0, math.inf, 0.5, 95.0)
    assert s.trips == 2


def test_reel_holds_while_tripped_and_reports_the_reason():
    params = default_parameters()
    core = build_core(params, 8.0)
    # the UAV rises: the controller wants to pay out, but the lowest point is at the limit
    inputs = ReelInputs(dr=3.22, dz=8.0, dz_rate=0.5, tension=1.0, departure_angle=0.5, clearance=0.05)
    outputs = [core.step(k * 0.01, inputs) for k in range(20)]
    assert all(o.trip.startswith('payout stopped: lowest point') for o in outputs)
    assert all(o.mode == 'fault' and o.drive == 'brake' for o in outputs)
    assert core.winch.deployed == 8.0
    assert outputs[-1].trips == 1
    inputs.clearance = 1.0
    released = [core.step(0.2 + k * 0.01, inputs) for k in range(20)]
    assert released[-1].trip == '' and released[-1].mode == 'catenary'
    assert core.winch.deployed > 8.0
