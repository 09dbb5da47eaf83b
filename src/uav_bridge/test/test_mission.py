"""MissionLogic: the phase sequence, refusals and retries, reel trips and the end time."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uav_bridge.mission import Inputs
from uav_bridge.mission import MissionConfig
from uav_bridge.mission import MissionLogic
from uav_bridge.mission import TripMonitor
from uav_bridge.mission_node import land_time

GROUND = np.array([0.0, 0.0, 0.0])


def test_station_of_the_thesis_flights():
    np.testing.assert_allclose(MissionConfig(altitude=30.0, radial=15.0).station(), [15.0, 0.0, 30.0])
    np.testing.assert_allclose(MissionConfig(altitude=5.0, radial=2.5, bearing=math.pi / 2).station(),
                               [0.0, 2.5, 5.0], atol=1e-12)
    assert MissionConfig().radial / MissionConfig().altitude == pytest.approx(0.46)


def test_full_sequence_requests_one_thing_at_a_time():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=100.0))
    out = logic.step(0.0, Inputs(connected=True, position_ready=False, position=GROUND, mode='STABILIZE'))
    assert out.phase == 'wait' and out.request is None
    out = logic.step(1.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='STABILIZE'))
    assert out.phase == 'guided' and out.request == ('set_mode', 'GUIDED')
    out = logic.step(1.1, Inputs(connected=True, position_ready=True, position=GROUND, mode='STABILIZE', busy=True))
    assert out.request is None                              # the request is still out
    out = logic.step(2.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED'))
    assert out.phase == 'arm' and out.request == ('arm', True)
    out = logic.step(3.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED', armed=True))
    assert out.phase == 'takeoff' and out.request == ('takeoff', 5.0)
    out = logic.step(4.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED', armed=True,
                                 answer=('takeoff', True, 'takeoff accepted')))
    assert out.phase == 'climb' and out.request is None and out.setpoint is None
    out = logic.step(9.0, Inputs(connected=True, position_ready=True, position=np.array([0.0, 0.0, 4.6]),
                                 mode='GUIDED', armed=True))
    assert out.phase == 'hold'
    np.testing.assert_allclose(out.setpoint, [2.5, 0.0, 5.0])
    out = logic.step(100.0, Inputs(connected=True, position_ready=True, position=np.array([2.5, 0.0, 5.0]),
                                   mode='GUIDED', armed=True))
    assert out.phase == 'land' and out.request == ('land', None) and out.reason == 'end of the mission'
    out = logic.step(101.0, Inputs(connected=True, position_ready=True, position=np.array([2.5, 0.0, 4.0]),
                                   mode='LAND', armed=True))
    assert out.phase == 'land' and out.request is None
    out = logic.step(120.0, Inputs(connected=True, position_ready=True, position=np.array([2.5, 0.0, 0.0]),
                                   mode='LAND', armed=False))
    assert out.phase == 'landed' and not logic.aborted


def test_refused_arming_is_retried_after_the_retry_period_with_the_reason_kept():
    logic = MissionLogic(MissionConfig(retry_period=2.0))
    base = dict(connected=True, position_ready=True, position=GROUND, mode='GUIDED')
    assert logic.step(0.0, Inputs(**base)).request == ('arm', True)
    out = logic.step(1.0, Inputs(**base, answer=('arm', False, 'PreArm: Need Position Estimate')))
    assert out.request is None and 'PreArm: Need Position Estimate' in out.reason
    assert logic.step(2.9, Inputs(**base)).request is None
    assert logic.step(3.1, Inputs(**base)).request == ('arm', True)


def test_reel_trip_aborts_and_lands_from_hold():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5))
    logic.phase = 'hold'
    flying = dict(connected=True, position_ready=True, position=np.array([2.5, 0.0, 5.0]), mode='GUIDED', armed=True)
    assert logic.step(10.0, Inputs(**flying)).setpoint is not None
    out = logic.step(11.0, Inputs(**flying, reel_fault='tension 95 N > 80 N'))
    assert out.phase == 'land' and out.request == ('land', None) and out.setpoint is None
    assert logic.aborted and out.reason == 'aborted: reel trip: tension 95 N > 80 N'
    out = logic.step(12.0, Inputs(**flying, answer=('land', False, 'land failed')))
    assert out.reason == 'aborted: reel trip: tension 95 N > 80 N'      # the abort reason stays


def test_leaving_guided_before_arming_asks_for_it_again():
    logic = MissionLogic(MissionConfig())
    base = dict(connected=True, position_ready=True, position=GROUND)
    logic.step(0.0, Inputs(**base, mode='GUIDED'))
    out = logic.step(1.0, Inputs(**base, mode='STABILIZE'))
    assert out.phase == 'guided' and out.request == ('set_mode', 'GUIDED') and 'STABILIZE' in out.reason


def test_trip_monitor_counts_a_trip_that_lasts():
    monitor = TripMonitor(abort_after=0.5)
    assert monitor.update(10.0, True, 'reel-in stopped') == ''
    assert monitor.update(10.02, False, '') == ''              # cleared within a tick: the mission flies on
    assert monitor.update(11.0, True, 'reel-in stopped') == ''
    assert monitor.update(11.48, True, 'reel-in stopped') == ''
    assert monitor.update(11.5, True, 'reel-in stopped') == 'reel-in stopped for 0.50 s'
    assert monitor.update(12.0, False, '') == 'reel-in stopped for 0.50 s'   # latched
    assert TripMonitor().update(3.0, True, 'reel in fault mode') == 'reel in fault mode'


def test_the_mission_lands_before_the_end_of_the_run_when_the_run_is_long_enough():
    assert land_time({'land_time': 0.0, 'land_before_end': 65.0}, 245.0) == 180.0
    assert land_time({'land_time': 100.0, 'land_before_end': 65.0}, 245.0) == 100.0   # the earlier of the two
    assert land_time({'land_time': 0.0, 'land_before_end': 65.0}, 20.0) == math.inf   # too short to land
    assert land_time({'land_time': 0.0, 'land_before_end': 65.0}, None) == math.inf   # end unknown (by hand)
    assert land_time({'land_time': 0.0, 'land_before_end': 0.0}, 245.0) == math.inf
