"""The mission report's side-by-side table of two known runs (the plant's tether against a straight line),
and its heave-correlation line with the amplitudes it is computed from.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from uav_bridge.mission.report import Run
from uav_bridge.mission.report import analyse
from uav_bridge.mission.report import comparison_lines
from uav_bridge.mission.report import summary_lines

STATION = (15.0, 0.0, 30.0)


def _run(name: str, model: str, offset: float, force) -> Run:
    """Holding from 2 s 'offset' m east of the station, altitude 0.1 x the heave; a constant tether force."""
    t = np.arange(0.0, 40.0, 0.01).round(2)
    heave = 0.3 * np.sin(0.7 * t)
    poses = np.column_stack([t, np.full_like(t, STATION[0] + offset), np.zeros_like(t), STATION[2] + 0.1 * heave])
    phases = [(0.1, 'arm', '', STATION), (0.2, 'takeoff', '', STATION), (0.3, 'climb', '', STATION),
              (2.0, 'hold', '', STATION)]
    empty = {'t': np.zeros(0)}
    tether = {**empty, 'clearance_deck': np.zeros(0), 'clearance_sea': np.zeros(0), 'fouling': np.zeros(0),
              'length': np.zeros(0)}
    forces = {'t': t, **{c: np.full_like(t, v) for c, v in zip('xyz', force, strict=True)}}
    return Run(Path(name), name, poses, phases, np.column_stack([t, heave]), [], tether,
               {**empty, 'dr': np.zeros(0), 'dz': np.zeros(0)}, {**empty, 'dz': np.zeros(0), 'initialized': np.zeros(0)},
               {**empty, 'length': np.zeros(0), 'mode': np.zeros(0)}, {**empty, 'count': np.zeros(0)}, 0.3, forces,
               model)


def test_two_runs_side_by_side_give_each_ones_hold_error_and_force():
    plant = analyse(_run('plant_run', 'plant', 0.05, (-2.72, 0.0, -14.83)))
    line = analyse(_run('line_run', 'straight_line', 0.03, (-6.17, 0.0, -12.39)))
    lines = comparison_lines([plant, line])
    assert lines[0].startswith('side by side')
    assert lines[1] == '  plant_run: plant | 0.050 / 0.050 | 0.060 | 14.83 / 2.72, 0.00'
    assert lines[2] == '  line_run: straight_line | 0.030 / 0.030 | 0.060 | 12.39 / 6.17, 0.00'
    assert comparison_lines([plant]) == []


def test_the_heave_correlation_comes_with_the_amplitudes_it_is_computed_from():
    r = analyse(_run('plant_run', 'plant', 0.0, (0.0, 0.0, -10.0)))
    text = '\n'.join(summary_lines(r))
    value = float(re.search(r'largest ([\d.]+) at lag', text).group(1))
    altitude, heave, coupled, share = (float(v) for v in re.search(
        r'altitude std ([\d.]+) m, heave std ([\d.]+) m; .* is ([\d.]+) m rms, ([\d.]+) % of the heave', text).groups())
    assert value == pytest.approx(1.0, abs=1e-3)                 # the altitude is the heave, scaled
    assert heave == pytest.approx(10 * altitude, rel=1e-3)       # by 0.1
    assert coupled == pytest.approx(altitude, abs=1e-4) and share == pytest.approx(10.0, abs=0.01)
