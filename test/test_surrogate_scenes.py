"""The UAV-surrogate scenes (Sec. 5.1, 6.1) end to end: platform, plant and smart reel, then the report.

The three scenes run briefly (``RUN`` s of sim time each, side by side in their own ROS
domains; lockstep keeps each one's numbers independent of the load) and
``tethersim report surrogate`` compares them: the catenary controller tracks its reference,
its mean UAV-end tension is an order of magnitude below the taut controller's, neither
nominal run trips the safety, and the braked reel fouls. The full-length numbers beside the
thesis's are measured with the scene durations (README, "Scenes").
"""

from __future__ import annotations

import re

import pytest

from tethersim_testing import processes_of
from tethersim_testing import start_tethersim
from tethersim_testing import tethersim

RUN = '10'
"""s of sim time per scene: 5 s of ramp-in, then 5 s of statistics (the report skips half the run)."""
SCENES = ('surrogate_catenary', 'surrogate_taut', 'surrogate_locked')


@pytest.fixture(scope='module')
def report(tmp_path_factory):
    root = tmp_path_factory.mktemp('surrogate')
    runs = {scene: root / scene for scene in SCENES}
    started = {scene: start_tethersim('run', scene, '--duration', RUN, '--rate', 'max', '--out', str(out))
               for scene, out in runs.items()}
    for scene, process in started.items():
        out, err = process.communicate(timeout=300)
        assert process.returncode == 0, f'{scene}: {out}{err}'
        assert not processes_of(runs[scene])
    result = tethersim('report', 'surrogate', *(str(runs[s]) for s in reversed(SCENES)), '--out',
                       str(root / 'report'), timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout, root / 'report'


def _cells(text: str, name: str) -> list[str]:
    line = next(line for line in text.splitlines() if line.startswith(name))
    return re.split(r'\s{2,}', line[34:].strip())


def test_report_verdicts_hold_on_the_short_runs(report):
    text, out = report
    verdicts = [line for line in text.splitlines() if line.startswith(('PASS', 'FAIL'))]
    assert len(verdicts) == 5, text
    assert not [line for line in verdicts if line.startswith('FAIL')], text
    ratio = float(re.search(r'mean tension taut/catenary: ([0-9.]+)x', text).group(1))
    assert ratio >= 10.0
    assert 'platform profile jonswap seed 1' in text
    for png in ('surrogate_length.png', 'surrogate_angles.png', 'surrogate_tension.png', 'surrogate_clearance.png'):
        assert (out / png).stat().st_size > 10_000


def test_table_has_one_column_per_run_in_catenary_taut_locked_order(report):
    text, _ = report
    header = next(line for line in text.splitlines() if 'thesis (cat. / taut)' in line)
    assert header.split()[-3:] == ['catenary', 'taut', 'locked']
    trips = _cells(text, 'safety trips')
    assert trips == ['0', '0', '0']
    catenary, taut, locked = (float(c) for c in _cells(text, 'length RMSE (m)')[1:])
    assert catenary <= 0.03 < min(taut, locked)
    fouled = [float(c) for c in _cells(text, 'time fouled (s)')]
    assert fouled[0] == fouled[1] == 0.0 < fouled[2]


def test_runs_of_different_profiles_are_refused(report, tmp_path):
    _, out = report
    root = out.parent
    params = root / 'surrogate_taut' / 'params' / 'platform.yaml'
    moved = tmp_path / 'taut'
    (moved / 'params').mkdir(parents=True)
    (moved / 'params' / 'platform.yaml').write_text(params.read_text().replace('jonswap', 'hpr2'))
    (moved / 'bag').symlink_to(root / 'surrogate_taut' / 'bag')
    result = tethersim('report', 'surrogate', str(root / 'surrogate_catenary'), str(moved), '--out',
                       str(tmp_path / 'report'))
    assert result.returncode == 2
    assert 'different platform profiles' in result.stderr and 'Traceback' not in result.stderr
