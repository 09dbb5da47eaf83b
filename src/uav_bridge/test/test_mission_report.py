"""The mission report on a known run that lands at the end: the hold window and the fouling figures stop where the
landing starts (its /mission/state phase ``return`` at the end of the mission, ``land`` on a reel trip).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from uav_bridge.mission.report import Run
from uav_bridge.mission.report import analyse
from uav_bridge.mission.report import figures
from uav_bridge.mission.report import summary_lines

STATION = (15.0, 0.0, 30.0)
LANDING = 60.0


def _landing_run(returns: bool = True) -> Run:
    """At the station from 2 s, heaving 0.1 m; lands from 60 s (returning over the pad first, or at once on a trip);
    the tether on the sea (fouled) from 70 s; reel trips at 30, 65 and 70 s.
    """
    t = np.arange(0.0, 80.0, 0.01).round(2)
    z = np.where(t < LANDING, 30.0 + 0.05 * np.sin(t), np.maximum(0.0, 30.0 - 0.5 * (t - LANDING)))
    poses = np.column_stack([t, np.full_like(t, 15.0), np.zeros_like(t), z])
    phases = [(0.1, 'arm', '', STATION), (0.2, 'takeoff', '', STATION), (0.3, 'climb', '', STATION),
              (2.0, 'hold', '', STATION)]
    phases += ([(LANDING, 'return', 'end of the mission', STATION), (LANDING + 5.0, 'land', 'end of the mission', STATION)]
               if returns else [(LANDING, 'land', 'aborted: reel trip: fouling', STATION)])
    fouled = t >= 70.0
    tether = {'t': t, 'clearance_deck': np.where(fouled, -1.0, 2.0), 'clearance_sea': np.where(fouled, 0.0, 3.0),
              'fouling': fouled.astype(float), 'length': np.full_like(t, 33.3),
              'tension_reel': np.where(t >= 72.0, 90.0, 20.0), 'tension_uav': np.where(t >= 72.0, 85.0, 18.0)}
    empty = {'t': np.zeros(0)}
    return Run(Path('landing'), 'landing', poses, phases, np.column_stack([t, 0.3 * np.sin(0.7 * t)]), [],
               tether, {**empty, 'dr': np.zeros(0), 'dz': np.zeros(0)},
               {**empty, 'dz': np.zeros(0), 'initialized': np.zeros(0)},
               {**empty, 'length': np.zeros(0), 'mode': np.zeros(0)},
               {'t': np.array([30.0, 65.0, 70.0]), 'count': np.array([1.0, 2.0, 3.0])}, 0.3)


@pytest.mark.parametrize('returns', [True, False], ids=['return, land', 'land on a trip'])
def test_the_hold_window_and_the_fouling_figures_end_where_the_landing_starts(returns):
    r = analyse(_landing_run(returns))
    assert r['landing'] == LANDING
    assert r['window'] == pytest.approx((2.0 + 5.0, LANDING))       # 5 s to settle after the arrival
    assert r['keeping']['peak_to_peak'] == pytest.approx(0.1, abs=1e-3)  # the descent is not in it
    assert r['fouling_events'] == 0 and r['fouled_time'] == 0.0 and r['min_deck'] == pytest.approx(2.3)
    assert r['trips'] == 1                                          # the trips at 65 and 70 s are in the landing
    lines = '\n'.join(summary_lines(r))
    assert 'held 7.0-60.0 s (53.0 s, from 5 s after the arrival within 0.5 m to the landing)' in lines
    assert 'fouling until the landing at 60.0 s: 0 events' in lines
    assert r['landing_figures']['trips'] == 2 and r['landing_figures']['fouled_time'] == pytest.approx(10.0)
    assert ('the landing from 60.0 s: reel safety trips 2, peak tension 90.0 N at the reel and 85.0 N at the UAV, '
            '10.0 s fouled') in lines


def test_without_a_landing_the_whole_run_counts():
    run = _landing_run()
    run.phases = [phase for phase in run.phases if phase[1] not in ('return', 'land')]
    r = analyse(run)
    assert r['landing'] == np.inf and r['window'] == pytest.approx((7.0, 79.99))
    assert r['fouling_events'] == 1 and r['fouled_time'] == pytest.approx(10.0) and r['trips'] == 3
    assert 'fouling: 1 events' in '\n'.join(summary_lines(r))


def test_a_lost_autopilot_is_listed_and_ends_the_hold_statistics_without_interpolating_across_its_gap():
    """The issue's run: the mission stayed in hold while the autopilot was killed, restarted and rebooted; poses
    stop for 20 s and resume with the UAV on the ground.
    """
    run = _landing_run()
    run.phases = [phase for phase in run.phases if phase[1] not in ('return', 'land')]
    t = run.poses[:, 0]
    keep = (t < 30.0) | (t >= 50.0)
    run.poses = run.poses[keep]
    run.poses[run.poses[:, 0] >= 50.0, 3] = 0.0
    ts = np.arange(0.0, 80.0, 0.25)
    run.uav_state = {'t': ts, 'up': ((ts < 30.0) | (ts >= 50.0)).astype(float), 'reboots': (ts >= 50.0).astype(float)}
    r = analyse(run)
    assert r['window'] == pytest.approx((7.0, 29.99))                        # the last pose before the gap
    assert r['keeping']['peak_to_peak'] == pytest.approx(0.1, abs=1e-3)       # the 30 m drop is not in it
    lags = r['xcorr'][0]
    assert lags.max() == pytest.approx(29.98 - 7.0, abs=1e-9)                 # heave samples of the window only
    lines = '\n'.join(summary_lines(r))
    assert ('autopilot: /uav/pose gap 30.0-50.0 s (20.0 s); link lost 30.0-50.0 s (20.0 s); autopilot reboot seen at '
            '50.0 s; the station-keeping figures stop at 30.0 s, before the first in the hold') in lines
    assert 'held 7.0-30.0 s' in lines


def test_a_run_without_outages_says_so():
    r = analyse(_landing_run())
    assert 'autopilot: no link loss, no reboot, no /uav/pose gap over 3 s' in '\n'.join(summary_lines(r))


@pytest.mark.parametrize('returns', [True, False], ids=['return, land', 'land on a trip'])
def test_the_figures_as_data(returns):
    f = figures(analyse(_landing_run(returns)))
    assert (f['outcome'], f['abort_reason']) == (('incomplete', None) if returns else ('aborted', 'reel trip: fouling'))
    assert f['success'] is False
    assert f['hold_time'] == pytest.approx(53.0) and f['landing_time'] == LANDING
    assert (f['peak_tension_reel'], f['peak_tension_uav']) == (90.0, 85.0)
    assert (f['reel_trips'], f['reel_trips_flying']) == (3, 1)
    assert f['fouled_time'] == 0.0 and f['landing_fouled_time'] == pytest.approx(10.0)
    assert f['least_clearance_deck'] == pytest.approx(2.3) and f['least_clearance_sea'] == 3.0
    assert f['landing_peak_tension_reel'] == 90.0
    assert f['altitude_peak_to_peak'] == pytest.approx(0.1, abs=1e-3)
    assert f['dz_rmse'] is None and f['length_rmse'] is None and f['shape_mean'] is None


@pytest.mark.parametrize('pad, outcome', [((15.0, 0.3), 'landed_on_pad'), ((0.75, 0.0), 'landed'), (None, 'landed')])
def test_the_outcome_of_a_landing_is_on_the_pad_only_within_its_radius(pad, outcome):
    """On the pad: the UAV (at x 15 m, y 0) touches down within PAD_RADIUS (0.5 m) of the pad's track; without a
    pad track (another UAV, or no pad ground) a landing is not on a pad.
    """
    run = _landing_run()
    track = None if pad is None else np.array([[t, pad[0], pad[1], 0.0] for t in np.arange(0.0, 80.0, 0.01)])
    run = replace(run, phases=run.phases + [(79.0, 'landed', 'end of the mission', STATION)], pad=track)
    f = figures(analyse(run))
    assert f['outcome'] == outcome and f['success'] is (outcome == 'landed_on_pad') and f['abort_reason'] is None
