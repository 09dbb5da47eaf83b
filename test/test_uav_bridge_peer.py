"""The MAVLink session against the ArduCopter test double: streams, conversions, commands, faults.

The double (``mavlink_peer_double.py``) runs at 5x real time with the EKF ready 10 s of its
time after boot, so each test takes a few wall seconds.
"""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mavlink_peer_double import ArduCopterPeerDouble
from uav_bridge.frames import euler_ned_to_quaternion_enu
from uav_bridge.mavlink import telemetry
from uav_bridge.mavlink.session import MavlinkSession
from uav_bridge.mavlink.session import STREAM_IDS
from uav_bridge.mavlink.session import SessionConfig

ORIGIN = (100.0, -50.0, 1.5)


class Collector:
    """Samples, statuses and log lines the session handed out, thread-safe."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.samples: list[tuple[object, float]] = []
        self.statuses = []
        self.logs: list[tuple[str, str]] = []

    def on_sample(self, sample, stamp):
        with self.lock:
            self.samples.append((sample, stamp))

    def on_status(self, status):
        with self.lock:
            self.statuses.append(status)

    def log(self, level, text):
        with self.lock:
            self.logs.append((level, text))

    def of(self, kind, since: float = -math.inf):
        with self.lock:
            return [s for s, stamp in self.samples if isinstance(s, kind) and stamp >= since]

    def last_status(self):
        with self.lock:
            return self.statuses[-1] if self.statuses else None

    def any_status(self, predicate) -> bool:
        with self.lock:
            return any(predicate(s) for s in self.statuses)


def wait_until(predicate, timeout: float = 30.0, what: str = 'condition') -> None:
    """Poll ``predicate`` until true; fail naming ``what`` when ``timeout`` wall seconds pass."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            pytest.fail(f'timed out waiting for {what}')
        time.sleep(0.02)


@pytest.fixture
def link():
    """A started test double and a session connected to it; both closed afterwards."""
    peer = ArduCopterPeerDouble(speedup=5.0, ekf_delay=10.0).start()
    collector = Collector()
    config = SessionConfig(url=f'tcp:127.0.0.1:{peer.port}', origin=ORIGIN, link_timeout=1.0,
                           reconnect_max=1.0, stream_timeout=1.0, status_period=0.2, arm_timeout=20.0,
                           stream_rates={'ATTITUDE': 20.0, 'LOCAL_POSITION_NED': 20.0, 'HIGHRES_IMU': 20.0,
                                         'GLOBAL_POSITION_INT': 5.0, 'EKF_STATUS_REPORT': 2.0})
    session = MavlinkSession(config, collector.on_sample, collector.on_status, collector.log)
    session.start()
    yield peer, session, collector
    session.stop()
    peer.close()


def _ready(collector):
    status = collector.last_status()
    return status is not None and status.position_ready and status.waiting_for == ''


def test_connects_requests_streams_and_waits_for_the_position_estimate(link):
    peer, session, collector = link
    wait_until(lambda: collector.of(telemetry.GlobalFix), what='first GLOBAL_POSITION_INT')
    requested = {msg_id: interval for _, msg_id, interval in peer.interval_requests}
    assert requested == {STREAM_IDS['ATTITUDE']: 50_000.0, STREAM_IDS['LOCAL_POSITION_NED']: 50_000.0,
                         STREAM_IDS['HIGHRES_IMU']: 50_000.0, STREAM_IDS['GLOBAL_POSITION_INT']: 200_000.0,
                         STREAM_IDS['EKF_STATUS_REPORT']: 500_000.0}
    hb = [m for _, m in peer.received if m.get_type() == 'HEARTBEAT']
    assert hb and hb[0].type == 18 and hb[0].get_srcSystem() == 255      # its own HEARTBEAT, onboard controller
    wait_until(lambda: _ready(collector), what='position estimate')
    # before the EKF used GPS: no pose, a global fix flagged invalid, and the reason said
    assert collector.any_status(lambda s: s.connected and 'no LOCAL_POSITION_NED' in s.waiting_for)
    assert not collector.of(telemetry.GlobalFix)[0].valid
    first_pose = collector.of(telemetry.Kinematics)[0]
    assert first_pose.boot_time >= peer.ekf_delay
    assert 'EKF3 IMU0 is using GPS' in collector.last_status().status_text
    # the offset of the stamping clock to the autopilot's time since boot, from the latest message
    now = time.monotonic()
    status = session.status(now)
    assert status.time_offset == pytest.approx(now - peer.sim_time(), abs=0.5)
    assert status.reconnects == 1 and status.reboots == 0


def test_known_pose_converts_to_enu_flu(link):
    peer, session, collector = link
    wait_until(lambda: _ready(collector), what='position estimate')
    roll, pitch, yaw = 0.1, -0.2, 2.5
    peer.set_state([10.0, 5.0, -15.0], [1.0, 2.0, -3.0], roll, pitch, yaw, rates=(0.01, 0.02, 0.03))
    mark = time.monotonic()
    wait_until(lambda: collector.of(telemetry.Kinematics, since=mark + 0.3)
               and collector.of(telemetry.ImuSample, since=mark + 0.3), what='the pinned pose')
    pose = collector.of(telemetry.Kinematics, since=mark + 0.3)[-1]
    np.testing.assert_allclose(pose.position, [105.0, -40.0, 16.5], atol=1e-4)
    np.testing.assert_allclose(pose.velocity, [2.0, 1.0, 3.0], atol=1e-6)
    np.testing.assert_allclose(pose.orientation, euler_ned_to_quaternion_enu(roll, pitch, yaw), atol=1e-6)
    body = Rotation.from_quat(pose.orientation)
    # the nose's heading in ENU is 90 deg - yaw (from east, counter-clockwise)
    nose = body.apply([1.0, 0.0, 0.0])
    assert math.atan2(nose[1], nose[0]) == pytest.approx(math.pi / 2 - yaw, abs=1e-6)
    imu = collector.of(telemetry.ImuSample, since=mark + 0.3)[-1]
    # the double's accelerometer reads -g rotated into the body: in FLU the world's up seen from the body
    np.testing.assert_allclose(body.apply(imu.linear_acceleration), [0.0, 0.0, 9.80665], atol=1e-5)
    np.testing.assert_allclose(imu.angular_velocity, [0.01, -0.02, -0.03], atol=1e-7)
    np.testing.assert_allclose(pose.angular_velocity, body.apply([0.01, -0.02, -0.03]), atol=1e-7)


def test_arm_refused_before_the_ekf_then_guided_takeoff_setpoint_land(link):
    peer, session, collector = link
    wait_until(lambda: collector.last_status() is not None and collector.last_status().mode == 'STABILIZE'
               and peer.sim_time() > peer.rc_mode_switch, what='the RC mode switch')
    assert session.set_mode('GUIDED').result(10).success
    result = session.arm().result(30)       # refused until the EKF uses GPS, retried with back-off
    assert result.success, result.message
    assert 'attempts' in result.message
    assert any('PreArm: Need Position Estimate' in text for _, text in collector.logs if 'refused' in text)
    takeoff = session.takeoff(10.0).result(10)
    assert takeoff.success, takeoff.message
    wait_until(lambda: peer.snapshot()['position'][2] < -9.5, what='take-off to 10 m')
    session.send_setpoint([ORIGIN[0] + 5.0, ORIGIN[1] + 10.0, ORIGIN[2] + 15.0])   # 10 m N, 5 m E, 15 m up
    wait_until(lambda: np.allclose(peer.snapshot()['position'], [10.0, 5.0, -15.0], atol=0.05),
               what='the setpoint')
    mark = time.monotonic()
    wait_until(lambda: collector.of(telemetry.Kinematics, since=mark), what='pose at the setpoint')
    np.testing.assert_allclose(collector.of(telemetry.Kinematics, since=mark)[-1].position,
                               [ORIGIN[0] + 5.0, ORIGIN[1] + 10.0, ORIGIN[2] + 15.0], atol=0.1)
    assert session.land().result(10).success
    wait_until(lambda: not peer.snapshot()['armed'], what='landing and disarm')
    wait_until(lambda: not collector.last_status().armed and collector.last_status().mode == 'LAND',
               what='the disarmed state')
    assert not session.set_mode('NOSUCHMODE').result(10).success


def test_takeoff_refused_when_not_armed_names_the_refusal(link):
    peer, session, collector = link
    wait_until(lambda: collector.last_status() is not None and collector.last_status().connected,
               what='the link')
    result = session.takeoff(5.0).result(10)
    assert not result.success
    assert 'takeoff failed' in result.message


def test_link_loss_marks_stale_reconnects_and_requests_streams_again(link):
    peer, session, collector = link
    wait_until(lambda: _ready(collector), what='position estimate')
    drop = time.monotonic()
    peer.drop_link(2.0)
    wait_until(lambda: collector.last_status().stale and not collector.last_status().connected,
               what='the stale flag')
    wait_until(lambda: collector.last_status().reconnects >= 2 and _ready(collector), timeout=30,
               what='reconnect and resume')
    # the double keeps streaming at the rates of the old connection (as ArduPilot keeps a channel's), so the
    # estimate can be ready before the double's thread has read the requests the session sent on the new one
    wait_until(lambda: peer.requests_since(drop) == set(STREAM_IDS.values()), what='streams requested again')
    assert collector.of(telemetry.Kinematics, since=drop + 2.0)
    assert any(level == 'warn' and 'link lost' in text for level, text in collector.logs)
    assert not any('link stale' in text for _, text in collector.logs)     # 'link lost' said it
    # a closed link, or a new one before its first HEARTBEAT, shows neither the armed flag nor the mode of the old
    assert collector.any_status(lambda s: not s.connected)
    assert not collector.any_status(lambda s: not s.connected and (s.mode or s.armed))


def test_heartbeat_gap_on_an_open_link_requests_streams_again(link):
    peer, session, collector = link
    wait_until(lambda: _ready(collector), what='position estimate')
    gap = time.monotonic()
    peer.silence(1.5)
    wait_until(lambda: collector.last_status().stale, what='the stale flag')
    wait_until(lambda: not collector.last_status().stale, what='heartbeats again')
    assert any(level == 'warn' and 'link stale' in text for level, text in collector.logs)   # open, but silent
    wait_until(lambda: peer.requests_since(gap) == set(STREAM_IDS.values()), what='streams requested again')
    assert collector.last_status().reconnects == 1


def test_reboot_is_detected_and_streams_requested_again(link):
    peer, session, collector = link
    wait_until(lambda: _ready(collector), what='position estimate')
    reboot = time.monotonic()
    peer.reboot()                           # forgets every requested interval
    wait_until(lambda: collector.last_status().reboots == 1, what='the reboot')
    wait_until(lambda: collector.of(telemetry.ImuSample, since=reboot + 0.5), what='IMU after the reboot')
    assert STREAM_IDS['ATTITUDE'] in peer.requests_since(reboot)
    assert any('rebooted' in text for _, text in collector.logs)
    assert peer.snapshot()['boots'] == 2


def test_garbage_bytes_are_counted_and_survived(link):
    peer, session, collector = link
    wait_until(lambda: collector.of(telemetry.ImuSample), what='IMU')
    before = collector.last_status().bad_packets
    for _ in range(5):
        peer.send_garbage(3000)
    mark = time.monotonic()
    wait_until(lambda: collector.last_status().bad_packets > before and collector.of(telemetry.ImuSample, mark + 0.3),
               what='telemetry after the garbage')
    assert session._thread.is_alive()
    assert session.callback_errors == 0
    assert collector.last_status().connected


def test_a_failing_consumer_does_not_stop_the_link():
    peer = ArduCopterPeerDouble(speedup=5.0, ekf_delay=1.0).start()
    statuses = []

    def broken(sample, stamp):
        raise RuntimeError('consumer bug')

    session = MavlinkSession(SessionConfig(url=f'tcp:127.0.0.1:{peer.port}', status_period=0.1), broken,
                             statuses.append)
    session.start()
    try:
        wait_until(lambda: session.callback_errors > 5 and statuses and statuses[-1].position_ready,
                   what='errors and telemetry')
        assert session._thread.is_alive()
    finally:
        session.stop()
        peer.close()


def test_waits_patiently_for_an_autopilot_that_is_not_there_yet():
    peer = ArduCopterPeerDouble(speedup=5.0, ekf_delay=1.0)
    port = peer.port
    peer.listener.close()                    # nothing listens yet
    statuses = []
    session = MavlinkSession(SessionConfig(url=f'tcp:127.0.0.1:{port}', reconnect_max=0.5, status_period=0.1),
                             on_status=statuses.append)
    session.start()
    try:
        wait_until(lambda: len(statuses) >= 3, what='status while waiting')
        assert statuses[-1].waiting_for == f'connection to tcp:127.0.0.1:{port}'
        assert not statuses[-1].connected and statuses[-1].stale
        peer.listener = peer._listen(port)
        peer.start()
        wait_until(lambda: statuses[-1].position_ready, what='the late autopilot')
    finally:
        session.stop()
        peer.close()


@pytest.mark.parametrize('url', ['tcp:localhost', 'serial:/dev/ttyS0:57600', 'tcp:host:99999', 'udp::14550'])
def test_bad_urls_are_refused_with_a_reason(url):
    with pytest.raises(ValueError, match='link URL'):
        MavlinkSession(SessionConfig(url=url))
