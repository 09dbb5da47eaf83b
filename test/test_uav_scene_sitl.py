"""`tethersim run` of the uav_sitl scene: real ArduCopter SITL, bridge and mission, recorded and reported."""

from __future__ import annotations

import psutil
import pytest

from sitl_process import SitlProcess
from sitl_process import sitl_binary
from sitl_process import put_on_instance
from sitl_process import sitl_unavailable
from tethersim_testing import processes_of
from tethersim_testing import tethersim
from tethersim_testing import installed_scene
from tethersim_testing import write_scene
from uav_bridge.mission.flight_report import read_flight

UNAVAILABLE = sitl_unavailable()
pytestmark = [pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or ''), pytest.mark.long_run]


def test_uav_sitl_scene_takes_off_holds_station_and_lands(tmp_path, monkeypatch):
    claim = SitlProcess(tmp_path / 'claim')          # a free SITL instance for this run
    try:
        scene = installed_scene('uav_sitl')
        put_on_instance(scene, claim.config.instance, tmp_path / 'sitl')
        path = write_scene(scene, tmp_path / 'uav_sitl.yaml')
        monkeypatch.setenv('ARDUPILOT_SITL_BIN', str(sitl_binary()))
        out = tmp_path / 'run'
        # the graph at half SITL's speed, so the flight fits the scene even when SITL falls behind its speedup
        result = tethersim('run', path, '--out', str(out), '--rate', '2', timeout=900)
    finally:
        claim.close()
    assert result.returncode == 0, result.stderr[-3000:]
    summary = (out / 'summary.txt').read_text()
    assert 'uav hold' in summary and 'thesis Sec. 6.3' in summary and 'not comparable' in summary
    assert (out / 'uav_flight.png').stat().st_size > 10_000
    flight = read_flight(out / 'bag' / 'bag_0.mcap')
    phases = [phase for _, phase, _, _ in flight['phases']]
    assert phases[0] == 'wait' and 'hold' in phases and phases[-1] == 'landed'
    assert flight['phases'][-1][2] == 'end of the mission'
    poses = flight['poses']
    assert poses[:, 3].max() == pytest.approx(30.0, abs=1.0)     # the station's altitude was reached
    assert poses[-1, 3] < 0.5
    assert processes_of(tmp_path) == []
    assert [p for p in psutil.process_iter(['cwd']) if p.info['cwd'] == str(tmp_path / 'sitl')] == []
