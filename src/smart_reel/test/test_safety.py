"""Safety trips: direction-gated, counted, persistent before they trip, released with hysteresis; the reel holds."""

from __future__ import annotations

import math

from smart_reel.reel import ReelInputs
from smart_reel.reel import build_core
from smart_reel.safety import SafetyLimits
from smart_reel.safety import SafetyMonitor
from smart_reel.tuning import default_parameters

LIMITS = SafetyLimits(min_clearance=0.2, min_departure_angle=0.0, max_tension=80.0, trip_delay=0.0)
DELAYED = SafetyLimits(min_clearance=0.2, min_departure_angle=math.radians(-20.0), max_tension=80.0, trip_delay=0.1,
                       hard_angle=math.radians(10.0))


def test_clearance_and_departure_angle_block_only_payout():
    s = SafetyMonitor(LIMITS)
    assert 'lowest point' in s.check(0.0, +1.0, 0.1, 0.5, 1.0)
    assert s.check(0.02, -1.0, 0.1, 0.5, 1.0) == ''
    assert 'departure angle' in s.check(0.04, +1.0, 1.0, math.radians(-2.0), 1.0)
    assert s.check(0.06, +1.0, 1.0, math.radians(5.0), 1.0) == ''


def test_tension_blocks_only_reel_in_and_trips_are_counted_once_per_event():
    s = SafetyMonitor(LIMITS)
    assert 'tension 90.0 N' in s.check(0.0, -1.0, math.inf, 0.5, 90.0)
    assert s.check(0.02, -1.0, math.inf, 0.5, 95.0)
    assert s.trips == 1
    assert s.check(0.04, +1.0, math.inf, 0.5, 95.0) == ''
    assert s.check(0.06, -1.0, math.inf, 0.5, 95.0)
    assert s.trips == 2


def test_a_reading_past_the_limit_for_one_tick_does_not_trip_one_that_lasts_does():
    """The default scene's abort: one 20 ms guide-arm reading of -22.6 deg tripped the reel and ended the mission."""
    s = SafetyMonitor(DELAYED)
    assert s.check(0.00, +1.0, 1.0, math.radians(-22.6), 1.0) == ''
    assert s.check(0.02, +1.0, 1.0, math.radians(5.0), 1.0) == ''
    assert s.trips == 0
    readings = [s.check(0.04 + 0.02 * k, +1.0, 1.0, math.radians(-22.6), 1.0) for k in range(6)]
    assert readings[:5] == [''] * 5
    assert readings[5] == 'payout stopped: departure angle -22.6 deg < -20 deg for 0.10 s'
    assert s.trips == 1


def test_past_the_hard_band_a_condition_trips_at_once():
    s = SafetyMonitor(DELAYED)
    assert 'departure angle -31.0 deg' in s.check(0.0, +1.0, 1.0, math.radians(-31.0), 1.0)
    s = SafetyMonitor(DELAYED)
    assert 'lowest point 0.000 m' in s.check(0.0, +1.0, 0.0, 0.0, 1.0)
    s = SafetyMonitor(DELAYED)
    assert 'tension 101.0 N' in s.check(0.0, -1.0, math.inf, 0.0, 101.0)


def test_a_trip_holds_until_the_condition_is_inside_the_release_band_then_recovers():
    s = SafetyMonitor(DELAYED)
    assert s.check(0.0, -1.0, math.inf, 0.0, 110.0)
    assert s.check(0.02, -1.0, math.inf, 0.0, 78.0), 'inside the limit but not by the 5 N release band: held'
    assert s.check(0.04, -1.0, math.inf, 0.0, 74.0) == '', 'recovered'
    assert s.trips == 1


def test_reel_holds_while_tripped_and_reports_the_reason():
    params = default_parameters()
    core = build_core(params, 8.0)
    # the UAV rises: the controller wants to pay out, but the lowest point is at the limit
    inputs = ReelInputs(dr=3.22, dz=8.0, dz_rate=0.5, tension=1.0, departure_angle=0.5, clearance=0.05)
    outputs = [core.step(k * 0.01, inputs) for k in range(30)]
    tripped = [o for o in outputs if o.trip]
    assert tripped and all(o.trip.startswith('payout stopped: lowest point') for o in tripped)
    assert all(o.mode == 'fault' and o.drive == 'brake' for o in outputs[-19:])
    assert outputs[-1].trips == 1
    inputs.clearance = 1.0
    released = [core.step(0.2 + k * 0.01, inputs) for k in range(20)]
    assert released[-1].trip == '' and released[-1].mode == 'catenary'
    assert core.winch.deployed > 8.0
