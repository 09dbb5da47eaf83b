"""The default scene as shipped, run to its end: the mission the README promises.

``make run`` flies ``outdoor_flight``: take-off, 175 s on station 30 m up and 15 m out over
the boat playing HPR 3, the return over the pad and the landing on it. The run must end as
the mission planned it (no abort), land on the pad, keep the landing's tension under the
reel's reel-in trip limit, never foul the tether, and estimate the relative altitude within
thesis Table 6.3's reach. Every figure is the mission report's, read from the run's bag.
"""

from __future__ import annotations

import math

import pytest

from uav_bridge.mission_report import PAD_RADIUS
from uav_bridge.mission_report import analyse
from uav_bridge.mission_report import load_run

from tethersim_testing import tethersim

DZ_RMSE_BOUND = 0.015
"""m, the in-flight estimator RMSE the default mission must keep (thesis Table 6.3: 8-12 mm)."""


@pytest.fixture(scope='module')
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp('default') / 'run'
    result = tethersim('run', 'outdoor_flight', '--out', str(out), timeout=1800)
    assert result.returncode == 0, result.stderr[-3000:]
    assert 'ended: end of the mission' in (out / 'summary.txt').read_text()
    return analyse(load_run(out / 'bag'))


def test_the_mission_ends_as_planned_and_lands_on_the_pad(report):
    assert report['phases'] == ['takeoff', 'climb', 'hold', 'return', 'land', 'landed']
    assert report['end'] == 'end of the mission'
    landed, distance = report['touchdown']
    assert distance <= PAD_RADIUS, f'touched down {distance:.2f} m from the pad at {landed:.1f} s'


def test_no_fouling_and_no_trip_on_station_and_the_landing_under_the_trip_limit(report):
    assert report['fouled_time'] == 0.0 and report['fouling_events'] == 0
    assert report['trips'] == 0
    landing = report['landing_figures']
    limit = report['run'].max_tension
    assert not math.isnan(limit)
    assert landing['tension_reel'] <= limit, f'{landing["tension_reel"]:.1f} N at the reel over {limit:g} N'
    assert landing['fouled_time'] == 0.0


def test_the_estimator_keeps_table_6_3s_reach_in_flight(report):
    common, error = report['dz_error']
    rmse = math.sqrt(float((error ** 2).mean()))
    assert rmse <= DZ_RMSE_BOUND, f'{rmse * 1e3:.1f} mm'
