"""SitlRunner's command line and its refusals (the real binary runs in test/test_uav_bridge_sitl.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from uav_bridge.sitl.runner import SitlConfig
from uav_bridge.sitl.runner import SitlError
from uav_bridge.sitl.runner import SitlRunner
from uav_bridge.sitl.runner import locate_binary


def test_command_line_and_port(tmp_path):
    defaults = tmp_path / 'copter.parm'
    defaults.write_text('FRAME_CLASS 1\n')
    runner = SitlRunner(SitlConfig(Path('/opt/arducopter'), defaults, tmp_path, instance=3, speedup=4.0,
                                   home='-35.3,149.1,584,0'))
    assert runner.command() == ['/opt/arducopter', '--model', '+', '--speedup', '4', '--defaults', str(defaults),
                                '-I3', '--home', '-35.3,149.1,584,0', '-w']
    assert runner.config.port == 5790
    assert runner.exit_status() is None


def test_parameters_override_the_defaults_file(tmp_path):
    defaults = tmp_path / 'copter.parm'
    defaults.write_text('FRAME_CLASS 1\nFRAME_TYPE\t0\n# comment\nMOT_THST_EXPO 0.65\n')
    runner = SitlRunner(SitlConfig(Path('/bin/true'), defaults, tmp_path / 'run', model='JSON:127.0.0.1',
                                   parameters=(('FRAME_TYPE', 1), ('SIM_RATE_HZ', 400))))
    runner.start()
    runner.process.wait(timeout=20)
    used = tmp_path / 'run' / 'defaults.parm'
    assert runner.command()[runner.command().index('--defaults') + 1] == str(used)
    # a lockstep (JSON) model runs without SITL's logger thread, whose timing the flight would feel
    assert used.read_text() == ('FRAME_CLASS 1\n# comment\nMOT_THST_EXPO 0.65\nFRAME_TYPE 1\nSIM_RATE_HZ 400\n'
                                'LOG_BACKEND_TYPE 0\n')
    assert defaults.read_text().startswith('FRAME_CLASS 1\nFRAME_TYPE\t0')


def test_the_logger_is_off_only_for_a_lockstep_model_and_unless_asked_for(tmp_path):
    defaults = tmp_path / 'copter.parm'
    defaults.write_text('FRAME_CLASS 1\n')
    own = SitlConfig(Path('/bin/true'), defaults, tmp_path, model='+', parameters=(('FRAME_TYPE', 1),))
    assert own.parameters_used == (('FRAME_TYPE', 1),)
    asked = SitlConfig(Path('/bin/true'), defaults, tmp_path, model='JSON:127.0.0.1',
                       parameters=(('log_backend_type', 1),))
    assert asked.parameters_used == (('log_backend_type', 1),)
    bare = SitlConfig(Path('/bin/true'), defaults, tmp_path, model='JSON:127.0.0.1')
    assert bare.parameters_used == (('LOG_BACKEND_TYPE', 0),) and bare.defaults_used == tmp_path / 'defaults.parm'


def test_refusals_name_the_file(tmp_path, monkeypatch):
    monkeypatch.delenv('ARDUPILOT_SITL_BIN', raising=False)
    with pytest.raises(SitlError, match='ARDUPILOT_SITL_BIN'):
        locate_binary('')
    with pytest.raises(SitlError, match='not an executable file'):
        locate_binary(str(tmp_path / 'missing'))
    with pytest.raises(SitlError, match='defaults file .*not found'):
        SitlRunner(SitlConfig(Path('/bin/true'), tmp_path / 'none.parm', tmp_path))
    monkeypatch.setenv('ARDUPILOT_SITL_BIN', '/bin/true')
    assert locate_binary('') == Path('/bin/true')
