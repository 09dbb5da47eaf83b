"""MissionLogic: the phase sequence, refusals and retries, reel trips and the end time."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uav_bridge.mission.logic import Inputs
from uav_bridge.mission.logic import MissionConfig
from uav_bridge.mission.logic import MissionLogic
from uav_bridge.mission.logic import TripMonitor
from uav_bridge.mission.node import land_time

GROUND = np.array([0.0, 0.0, 0.0])


def test_station_of_the_thesis_flights():
    np.testing.assert_allclose(MissionConfig(altitude=30.0, radial=15.0).station(), [15.0, 0.0, 30.0])
    np.testing.assert_allclose(MissionConfig(altitude=5.0, radial=2.5, bearing=math.pi / 2).station(),
                               [0.0, 2.5, 5.0], atol=1e-12)
    assert MissionConfig().radial / MissionConfig().altitude == pytest.approx(0.46)


def test_full_sequence_requests_one_thing_at_a_time():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=100.0, return_speed=1.0))
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
    assert out.phase == 'return' and out.request is None and out.reason == 'end of the mission'
    out = logic.step(103.0, Inputs(connected=True, position_ready=True, position=np.array([0.2, 0.0, 5.0]),
                                   mode='GUIDED', armed=True))
    assert out.phase == 'land' and out.request == ('land', None) and out.setpoint is None
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


def test_a_reel_trip_without_a_return_holds_the_station_and_never_lands_beside_the_boat():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=100.0))
    logic.phase = 'hold'
    flying = dict(connected=True, position_ready=True, position=np.array([2.5, 0.0, 5.0]), mode='GUIDED', armed=True)
    assert logic.step(10.0, Inputs(**flying)).setpoint is not None
    out = logic.step(11.0, Inputs(**flying, reel_fault='tension 95 N > 80 N'))
    assert out.phase == 'hold' and out.request is None and np.allclose(out.setpoint, [2.5, 0.0, 5.0])
    assert logic.aborted and out.reason == 'aborted: reel trip: tension 95 N > 80 N'
    out = logic.step(12.0, Inputs(**flying, reel_fault='tension 95 N > 80 N'))
    assert out.phase == 'hold' and out.reason == 'aborted: reel trip: tension 95 N > 80 N'   # the abort reason stays


def test_a_reel_trip_with_a_return_returns_over_the_pad_and_lands_there():
    """The default scene's abort landed the UAV 10-15 m from the boat with the reel braked: 47.8 s of tether fouled."""
    logic = MissionLogic(MissionConfig(altitude=30.0, radial=15.0, land_time=180.0, pad=(0.75, 0.0), return_speed=0.5,
                                       return_height=3.5))
    logic.phase = 'hold'
    flying = dict(connected=True, position_ready=True, position=np.array([15.0, 0.0, 30.0]), mode='GUIDED', armed=True)
    out = logic.step(38.5, Inputs(**flying, reel_fault='payout stopped: departure angle -22.6 deg < -20 deg'))
    assert out.phase == 'return' and out.request is None and logic.aborted
    assert out.reason == 'aborted: reel trip: payout stopped: departure angle -22.6 deg < -20 deg'
    t = 38.5
    while out.phase == 'return':
        t += 0.1
        over = logic.return_setpoint(t)
        out = logic.step(t, Inputs(**{**flying, 'position': over}, reel_fault='still'))
    assert out.phase == 'land' and out.request == ('land', None)
    assert np.allclose(over, [0.75, 0.0, 3.5])
    assert out.reason.startswith('aborted: reel trip: payout stopped')


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


FLYING = dict(connected=True, position_ready=True, mode='GUIDED', armed=True)


def test_the_end_returns_over_the_pad_at_the_hold_altitude_at_the_return_speed_then_lands():
    logic = MissionLogic(MissionConfig(altitude=30.0, radial=15.0, land_time=100.0, pad=(0.0, 0.0),
                                       return_speed=1.0, return_tolerance=0.5))
    logic.phase = 'hold'
    station = np.array([15.0, 0.0, 30.0])
    setpoints = []
    for k in range(0, 200):
        t = 100.0 + 0.1 * k
        behind = max(0.0, 15.0 - 0.1 * (k - 10)) if k >= 10 else 15.0      # the UAV 1 s behind the setpoint
        out = logic.step(t, Inputs(**FLYING, position=np.array([behind, 0.0, 30.0])))
        if out.phase != 'return':
            break
        setpoints.append((t, out.setpoint))
    assert out.phase == 'land' and out.request == ('land', None) and out.setpoint is None
    times = np.array([t for t, _ in setpoints])
    path = np.array([p for _, p in setpoints])
    np.testing.assert_allclose(path[0], station)                        # from the station
    np.testing.assert_allclose(path[:, 2], 30.0)                        # at the hold altitude
    np.testing.assert_allclose(path[:, 1], 0.0)                         # straight toward the pad
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert steps.max() <= 1.0 * 0.1 + 1e-9                              # the speed bound, 1 m/s at 10 Hz
    np.testing.assert_allclose(path[times >= 115.0], [[0.0, 0.0, 30.0]] * int((times >= 115.0).sum()))
    assert times[-1] >= 115.0 - 1e-9                                    # 15 m at 1 m/s before the landing
    assert logic.outcome == 'end of the mission' and not logic.aborted


def test_a_return_height_brings_the_uav_down_the_line_toward_the_pad_then_lands():
    """With ``return_height`` the return goes in a straight line from the station to over the pad at that
    height, at ``return_speed`` along the line: Δr/Δz stays away from 0 all the way down (0.5 to 0.21 here).
    """
    logic = MissionLogic(MissionConfig(altitude=30.0, radial=15.0, land_time=100.0, pad=(0.75, 0.0),
                                       return_speed=0.5, return_height=3.5, return_tolerance=0.5))
    logic.phase = 'hold'
    path = []
    for k in range(0, 1000):
        t = 100.0 + 0.1 * k
        position = path[-1] if path else np.array([15.0, 0.0, 30.0])      # the UAV one step behind
        out = logic.step(t, Inputs(**FLYING, position=position))
        if out.phase != 'return':
            break
        path.append(out.setpoint)
    assert out.phase == 'land' and out.request == ('land', None)
    path = np.array(path)
    end = np.array([0.75, 0.0, 3.5])
    np.testing.assert_allclose(path[0], [15.0, 0.0, 30.0])
    assert np.linalg.norm(path[-1] - end) <= 0.5 * 0.1 + 1e-9           # lands once the setpoint is there
    direction = (end - path[0]) / np.linalg.norm(end - path[0])
    off_line = (path - path[0]) - np.outer((path - path[0]) @ direction, direction)
    np.testing.assert_allclose(off_line, 0.0, atol=1e-12)                # a straight line
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert steps.max() <= 0.5 * 0.1 + 1e-9 and steps[:-1].min() >= 0.5 * 0.1 - 1e-9   # at 0.5 m/s along it
    ratio = np.hypot(path[:, 0] - 0.0, path[:, 1]) / path[:, 2]         # from the guide way at the origin
    assert ratio.min() >= 0.75 / 3.5 and ratio.max() == pytest.approx(0.5)


def test_the_return_waits_for_the_uav_over_the_pad_and_goes_on_through_a_reel_trip():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=10.0, pad=(1.0, -1.0),
                                       return_speed=1.0, return_tolerance=0.5))
    logic.phase = 'hold'
    far = np.array([2.5, 0.0, 5.0])
    assert logic.step(10.0, Inputs(**FLYING, position=far)).phase == 'return'
    out = logic.step(20.0, Inputs(**FLYING, position=far))
    assert out.phase == 'return'                                        # the setpoint is over the pad, the UAV not
    np.testing.assert_allclose(out.setpoint, [1.0, -1.0, 5.0])
    out = logic.step(20.1, Inputs(**FLYING, position=far, reel_fault='fouling'))
    assert out.phase == 'return' and out.request is None and not logic.aborted     # toward the guide way still
    np.testing.assert_allclose(out.setpoint, [1.0, -1.0, 5.0])
    out = logic.step(20.2, Inputs(**FLYING, position=np.array([1.2, -1.0, 5.0]), reel_fault='fouling'))
    assert out.phase == 'land' and out.request == ('land', None) and logic.outcome == 'end of the mission'


def test_the_setpoint_of_the_return_depends_on_the_step_time_alone():
    configs = MissionConfig(altitude=30.0, radial=15.0, land_time=50.0, return_speed=1.0)
    a, b = MissionLogic(configs), MissionLogic(configs)
    for logic in (a, b):
        logic.phase = 'hold'
        logic.step(50.0, Inputs(**FLYING, position=np.array([15.0, 0.0, 30.0])))
    a.step(51.0, Inputs(**FLYING, position=np.array([14.0, 0.0, 30.0])))
    out_a = a.step(57.3, Inputs(**FLYING, position=np.array([9.0, 0.0, 30.0])))
    out_b = b.step(57.3, Inputs(**FLYING, position=np.array([12.0, 0.0, 31.0])))
    np.testing.assert_allclose(out_a.setpoint, out_b.setpoint)
    np.testing.assert_allclose(out_a.setpoint, [15.0 - 7.3, 0.0, 30.0])


def test_the_end_before_take_off_lands_without_a_return():
    logic = MissionLogic(MissionConfig(land_time=5.0))
    out = logic.step(5.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED'))
    assert out.phase == 'landed' and logic.outcome == 'end of the mission'       # disarmed: on the ground


def test_return_speed_zero_lands_where_the_uav_is():
    logic = MissionLogic(MissionConfig(altitude=30.0, radial=15.0, land_time=10.0, return_speed=0.0))
    logic.phase = 'hold'
    out = logic.step(10.0, Inputs(**FLYING, position=np.array([15.0, 0.0, 30.0])))
    assert out.phase == 'land' and out.request == ('land', None) and out.setpoint is None


def _flying(logic: MissionLogic, t: float = 10.0, reboots: int = 0) -> None:
    """Step a mission of a 5 m station up to its hold at ``t``."""
    up = Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED', armed=True, reboots=reboots)
    logic.step(t - 3.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='GUIDED', reboots=reboots))
    logic.step(t - 2.0, up)
    logic.step(t - 1.0, Inputs(**{**up.__dict__, 'answer': ('takeoff', True, 'takeoff accepted')}))
    assert logic.step(t, Inputs(**{**up.__dict__, 'position': np.array([2.5, 0.0, 5.0])})).phase == 'hold'


HOLDING = dict(connected=True, position_ready=True, position=np.array([2.5, 0.0, 5.0]), mode='GUIDED', armed=True)


def test_a_link_down_longer_than_the_grace_ends_the_mission_without_a_request_or_setpoint():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=100.0, link_grace=4.0))
    _flying(logic)
    down = Inputs(connected=False, position=np.array([2.5, 0.0, 5.0]), waiting_for='connection to tcp:x:5760')
    out = logic.step(11.0, down)
    assert (out.phase, out.request, out.setpoint) == ('hold', None, None)
    assert out.reason == 'link to the autopilot down since 11.00 s'
    out = logic.step(14.9, down)
    assert out.phase == 'hold' and not logic.aborted
    out = logic.step(15.0, down)
    assert out.phase == 'lost' and logic.aborted and out.request is None and out.setpoint is None
    assert out.reason == ('aborted: autopilot lost: link to the autopilot down for 4.0 s since 11.00 s '
                          '(waiting for connection to tcp:x:5760)')
    # nothing brings it back: not the link, not the end time, not a reel trip
    out = logic.step(120.0, Inputs(**HOLDING, reel_fault='tension'))
    assert (out.phase, out.request, out.setpoint) == ('lost', None, None)


def test_a_link_back_within_the_grace_with_the_uav_flying_in_guided_resumes_the_hold():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, link_grace=4.0))
    _flying(logic)
    logic.step(11.0, Inputs(connected=False))
    out = logic.step(13.0, Inputs(**HOLDING))
    assert out.phase == 'hold' and out.setpoint is not None and not logic.aborted


def test_a_reboot_in_flight_ends_the_mission_at_once_a_reboot_on_the_ground_does_not():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5))
    logic.step(0.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='STABILIZE', reboots=1))
    _flying(logic, reboots=1)                  # rebooted before the take-off: counts from there
    out = logic.step(11.0, Inputs(**{**HOLDING, 'armed': False, 'mode': 'STABILIZE'}, reboots=2))
    assert out.phase == 'lost' and logic.aborted
    assert out.reason == 'aborted: autopilot lost: the autopilot rebooted in flight (reboot 2 of the link, seen at 11.00 s)'


@pytest.mark.parametrize('change, reason', [
    ({'armed': False, 'mode': 'STABILIZE'}, 'the autopilot disarmed in flight (mode STABILIZE) at 13.00 s'),
    ({'mode': 'LAND'}, 'the autopilot came back from a link gap in LAND, not GUIDED, at 13.00 s')])
def test_an_autopilot_back_from_a_gap_disarmed_or_out_of_guided_ends_the_mission(change, reason):
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, link_grace=4.0))
    _flying(logic)
    logic.step(11.0, Inputs(connected=False))
    out = logic.step(13.0, Inputs(**{**HOLDING, **change}))
    assert out.phase == 'lost' and out.reason == f'aborted: autopilot lost: {reason}'


def test_a_landing_whose_link_closes_is_not_taken_for_landed():
    logic = MissionLogic(MissionConfig(altitude=5.0, radial=2.5, land_time=20.0, link_grace=4.0))
    _flying(logic)
    assert logic.step(20.0, Inputs(**HOLDING)).phase == 'land'
    out = logic.step(21.0, Inputs(connected=False, armed=False))    # a closed link clears armed
    assert out.phase == 'land' and out.request is None
    assert logic.step(25.0, Inputs(connected=False)).phase == 'lost'


def test_an_unanswered_request_ends_the_mission_in_any_phase():
    logic = MissionLogic(MissionConfig())
    logic.step(0.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='STABILIZE'))
    failure = 'no answer from /uav/set_mode within 15 s'
    out = logic.step(20.0, Inputs(connected=True, position_ready=True, position=GROUND, mode='STABILIZE', busy=True,
                                  link_failure=failure))
    assert (out.phase, out.request) == ('lost', None) and out.reason == f'aborted: autopilot lost: {failure}'
