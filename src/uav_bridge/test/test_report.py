"""Station-keeping statistics of the flight report on known tracks."""

from __future__ import annotations

import numpy as np
import pytest

from uav_bridge.mission.flight_report import Outage
from uav_bridge.mission.flight_report import clip_to_outages
from uav_bridge.mission.flight_report import hold_interval
from uav_bridge.mission.flight_report import link_outages
from uav_bridge.mission.flight_report import station_keeping


def test_station_keeping_of_a_circle_with_heave():
    t = np.linspace(0.0, 2 * np.pi, 2000, endpoint=False)
    positions = np.column_stack([15.0 + 0.6 * np.cos(t), 0.6 * np.sin(t), 30.0 + 0.54 * np.sin(3 * t)])
    stats = station_keeping(positions, (15.0, 0.0, 30.0))
    assert stats['peak_to_peak'] == pytest.approx(1.08, abs=1e-6)
    assert stats['std'] == pytest.approx(0.54 / np.sqrt(2), rel=1e-3)
    assert stats['radius'] == pytest.approx(0.6, abs=1e-6)
    assert stats['from_station'] == pytest.approx(np.hypot(0.6, 0.54), abs=2e-3)


def test_hold_window_opens_when_the_uav_reaches_the_station():
    station = (2.5, 0.0, 5.0)
    phases = [(1.0, 'wait', '', station), (40.0, 'climb', '', station), (50.0, 'hold', '', station),
              (90.0, 'land', 'end of the mission', station)]
    t = np.arange(0.0, 100.0, 0.5)
    # at 4.6 m until 50 s, then crossing 2.5 m horizontally at 0.1 m/s: within 0.5 m at 70 s
    x = np.clip((t - 50.0) * 0.1, 0.0, 2.5)
    poses = np.column_stack([t, x, np.zeros_like(t), np.where(t < 50.0, 4.6, 5.0)])
    assert hold_interval(phases, poses, settle=0.0) == (70.0, 90.0)
    assert hold_interval(phases, poses) == (75.0, 90.0)                  # 5 s to settle after the arrival
    assert hold_interval(phases, poses, arrival=3.0) == (55.0, 90.0)
    assert hold_interval(phases[:3], poses) == (75.0, np.inf)
    assert hold_interval(phases[:2], poses) is None
    assert hold_interval(phases, poses, settle=20.0) is None            # would open after the hold ended
    poses[:, 1] = 0.0                                     # never came within 0.5 m of the station
    assert hold_interval(phases, poses) is None


def test_outages_after_the_link_first_came_up_and_the_window_they_leave():
    t = np.arange(0.0, 10.0, 1.0)
    up = np.array([0, 0, 1, 1, 0, 0, 1, 1, 1, 0], dtype=bool)        # down at the start: not an outage
    reboots = np.array([0, 0, 0, 0, 0, 0, 1, 1, 1, 1])
    poses = np.array([2.0, 2.5, 3.0, 3.5, 6.0, 6.5, 7.0])             # none from 3.5 to 6 s
    outages = link_outages(t, up, reboots, poses, gap=1.0)
    assert outages == [Outage(3.5, 6.0, 'pose gap'), Outage(4.0, 6.0, 'link lost'), Outage(6.0, 6.0, 'reboot'),
                       Outage(9.0, np.inf, 'link lost')]
    assert [o.text() for o in outages] == ['/uav/pose gap 3.5-6.0 s (2.5 s)', 'link lost 4.0-6.0 s (2.0 s)',
                                           'autopilot reboot seen at 6.0 s', 'link lost from 9.0 s to the end']
    assert link_outages(t, up, reboots, poses)[0] == Outage(4.0, 6.0, 'link lost')     # 2.5 s: under POSE_GAP
    at_end = link_outages(t, up, reboots, poses, gap=1.0, end=9.0)
    assert Outage(7.0, np.inf, 'pose gap') in at_end
    assert Outage(9.0, np.inf, 'link lost') not in at_end            # the run's nodes stopping at its end
    assert Outage(7.0, np.inf, 'pose gap').text() == '/uav/pose gap from 7.0 s to the end'
    assert clip_to_outages((2.0, np.inf), outages, poses) == (2.0, 3.5)
    assert clip_to_outages((6.5, 8.0), outages, poses) == (6.5, 8.0)
    assert clip_to_outages((3.0, np.inf), outages, poses) is None      # one pose left
    assert clip_to_outages((4.0, 8.0), outages, poses) is None         # opens inside an outage
    assert clip_to_outages(None, outages, poses) is None
