"""The check that SITL took a scene's parameters, against the real ArduCopter SITL.

SITL skips a name it lacks in its defaults file without a word; the check asks for each name
on SITL's second MAVLink port and names the unknown ones. Skipped only where no SITL binary
runs (see ``sitl_process.py``).
"""

from __future__ import annotations


import pytest

from sitl_process import SitlProcess
from sitl_process import connect_when_listening
from sitl_process import sitl_unavailable
from uav_bridge.sitl.parameter_check import check_parameters

UNAVAILABLE = sitl_unavailable()
pytestmark = pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or '')


def test_a_known_name_is_confirmed_and_an_unknown_one_named(tmp_path):
    wanted = {'WP_SPD_UP': 0.5, 'WPNAV_SPEED_UP': 50.0, 'FRAME_TYPE': 1.0}   # the second: the name before 4.7
    sitl = SitlProcess(tmp_path, speedup=10.0, parameters=tuple(wanted.items()))
    sitl.start()
    try:
        # SITL runs once a client holds its first port (the bridge's); the check uses the second
        with connect_when_listening(sitl.config.port):
            result = check_parameters(f'tcp:127.0.0.1:{sitl.config.port + 2}', wanted, patience=6,
                                      connect_timeout=60)
    finally:
        sitl.close()
    assert result.confirmed == {'WP_SPD_UP': 0.5, 'FRAME_TYPE': 1.0}
    assert result.unknown == ['WPNAV_SPEED_UP'] and not result.different and not result.error
    assert result.problem() == ('SITL has no parameter WPNAV_SPEED_UP (it skips such a name in its defaults file; '
                                'check the name for this ArduPilot version)')
