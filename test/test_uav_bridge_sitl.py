"""The MAVLink session against a real ArduCopter SITL: the GUIDED sequence, and SITL killed mid-flight.

Skipped only where no SITL binary runs (see ``sitl_process.py``). SITL runs at 10x real time
with the telemetry rates lowered to 10 Hz of its time, so one test takes 15-30 s of wall time.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from sitl_process import SitlProcess
from sitl_process import sitl_unavailable
from test_uav_bridge_peer import Collector
from test_uav_bridge_peer import wait_until
from uav_bridge.mavlink import telemetry
from uav_bridge.mavlink.session import MavlinkSession
from uav_bridge.mavlink.session import STREAM_IDS
from uav_bridge.mavlink.session import SessionConfig

UNAVAILABLE = sitl_unavailable()
pytestmark = pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or '')
ORIGIN = (2.0, -3.0, 1.0)


@pytest.fixture
def sitl_link(tmp_path):
    """A SITL instance and a session connected to it; SITL is killed and checked gone afterwards."""
    sitl = SitlProcess(tmp_path, speedup=10.0)
    collector = Collector()
    config = SessionConfig(url=sitl.url(), origin=ORIGIN, link_timeout=1.0, reconnect_max=1.0, stream_timeout=1.0,
                           status_period=0.2, arm_timeout=60.0, command_timeout=10.0,
                           stream_rates={'ATTITUDE': 10.0, 'LOCAL_POSITION_NED': 10.0, 'HIGHRES_IMU': 10.0,
                                         'GLOBAL_POSITION_INT': 5.0, 'EKF_STATUS_REPORT': 2.0})
    session = MavlinkSession(config, collector.on_sample, collector.on_status, collector.log)
    sitl.start()
    session.start()
    try:
        yield sitl, session, collector
    finally:
        session.stop()
        sitl.close()
        assert sitl.leftovers() == []
        print((tmp_path / 'sitl.log').read_text(errors='replace')[-2000:])


def _status(collector):
    return collector.last_status()


def _altitude(collector, since=-np.inf):
    poses = collector.of(telemetry.Kinematics, since)
    return poses[-1].position[2] - ORIGIN[2] if poses else -np.inf


def test_guided_sequence_with_real_arducopter(sitl_link):
    sitl, session, collector = sitl_link
    # the default RC input switches to STABILIZE 2.5 s of SITL time after boot: set GUIDED after it
    wait_until(lambda: _status(collector) is not None and _status(collector).connected, timeout=60, what='HEARTBEAT')
    wait_until(lambda: collector.of(telemetry.ImuSample), timeout=60, what='IMU stream')
    wait_until(lambda: collector.of(telemetry.ImuSample)[-1].boot_time > 3.0, timeout=60, what='RC mode switch')
    assert session.set_mode('GUIDED').result(30).success
    assert not _status(collector).position_ready      # ~40 s of SITL time before the EKF uses GPS
    assert 'no LOCAL_POSITION_NED' in _status(collector).waiting_for
    armed = session.arm().result(90)                  # refused until then: retried with back-off
    assert armed.success, armed.message
    refusals = [text for _, text in collector.logs if text.startswith('arming, attempt')]
    assert refusals and any('PreArm' in text or 'arm failed' in text for text in refusals)
    assert _status(collector).position_ready
    imu = collector.of(telemetry.ImuSample)[-1]
    assert imu.linear_acceleration[2] == pytest.approx(9.81, abs=0.3)      # FLU: +g on z, standing level
    takeoff = session.takeoff(10.0).result(30)
    assert takeoff.success, takeoff.message
    wait_until(lambda: _altitude(collector) > 9.5, timeout=60, what='take-off to 10 m')
    session.send_setpoint([ORIGIN[0] + 5.0, ORIGIN[1] + 10.0, ORIGIN[2] + 15.0])   # 10 m N, 5 m E, 15 m up
    target = np.array([ORIGIN[0] + 5.0, ORIGIN[1] + 10.0, ORIGIN[2] + 15.0])
    wait_until(lambda: np.linalg.norm(collector.of(telemetry.Kinematics)[-1].position - target) < 0.5, timeout=60,
               what='the position setpoint')
    assert _status(collector).ready
    fix = collector.of(telemetry.GlobalFix)[-1]
    assert fix.valid and fix.latitude == pytest.approx(-35.36326 + 10.0 / 111_000, abs=3e-5)
    assert session.land().result(30).success
    wait_until(lambda: not _status(collector).armed, timeout=120, what='landing and auto-disarm')
    assert _altitude(collector) < 0.5
    assert _status(collector).mode == 'LAND'


def test_sitl_killed_and_restarted_mid_flight(sitl_link):
    sitl, session, collector = sitl_link
    wait_until(lambda: _status(collector) is not None and _status(collector).position_ready, timeout=90,
               what='position estimate')
    assert session.set_mode('GUIDED').result(30).success
    assert session.arm().result(60).success
    assert session.takeoff(10.0).result(30).success
    wait_until(lambda: _altitude(collector) > 5.0, timeout=60, what='climbing')
    killed = time.monotonic()
    sitl.kill()
    wait_until(lambda: _status(collector).stale and not _status(collector).connected, timeout=10,
               what='the stale flag')
    assert sitl.leftovers() == []
    sitl.start(wipe=False)
    wait_until(lambda: _status(collector).connected and _status(collector).reconnects >= 2, timeout=60,
               what='reconnect')
    # the new SITL sends telemetry only because the bridge asked for it again
    wait_until(lambda: any(s.boot_time < 10.0 for s in collector.of(telemetry.ImuSample, since=killed)), timeout=60,
               what='streams of the restarted SITL')
    # its time since boot went backwards (the status follows the samples of the same read)
    wait_until(lambda: _status(collector).reboots >= 1, timeout=10, what='the reboot in the status')
    assert _status(collector).reboots == 1
    assert any('rebooted' in text for _, text in collector.logs)
    assert all(session.stream_requests[name] >= 2 for name in STREAM_IDS)
    wait_until(lambda: _status(collector).position_ready, timeout=90, what='position estimate after restart')
    assert not _status(collector).armed
