"""What the default scene as shipped must do, run to its end: the mission the README promises.

``make run`` flies ``outdoor_flight``: take-off, 175 s on station 30 m up and 15 m out over
the boat playing HPR 3, the return over the pad and the landing on it. The run must end as
the mission planned it (no abort), land on the pad, keep the landing's tension under the
reel's reel-in trip limit, never foul the tether or trip the reel on station, and estimate
the relative altitude within thesis Table 6.3's reach. Every figure is the mission report's
(:func:`uav_bridge.mission.report.analyse`), read from the run's bag.
"""

from __future__ import annotations

import math

from uav_bridge.mission.report import PAD_RADIUS

DZ_RMSE_BOUND = 0.015
"""m, the in-flight estimator RMSE the default mission must keep (thesis Table 6.3: 8-12 mm)."""


def check_default_mission(report: dict) -> None:
    """Assert the default mission's outcome on its mission report (``analyse``'s result)."""
    assert report['phases'] == ['takeoff', 'climb', 'hold', 'return', 'land', 'landed'], report['phases']
    assert report['end'] == 'end of the mission', report['end']
    landed, distance = report['touchdown']
    assert distance <= PAD_RADIUS, f'touched down {distance:.2f} m from the pad at {landed:.1f} s'
    assert report['fouled_time'] == 0.0 and report['fouling_events'] == 0
    assert report['trips'] == 0
    landing = report['landing_figures']
    limit = report['run'].max_tension
    assert not math.isnan(limit)
    assert landing['tension_reel'] <= limit, f'{landing["tension_reel"]:.1f} N at the reel over {limit:g} N'
    _, error = report['dz_error']
    rmse = math.sqrt(float((error ** 2).mean()))
    assert rmse <= DZ_RMSE_BOUND, f'{rmse * 1e3:.1f} mm'
