"""The mavlink_bridge node against the ArduCopter test double: topics, frames, services, setpoints."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import threading
from pathlib import Path

import pytest

rclpy = pytest.importorskip('rclpy')

from ament_index_python.packages import get_package_prefix  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from geometry_msgs.msg import TwistStamped  # noqa: E402
from rcl_interfaces.msg import Log  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import DurabilityPolicy  # noqa: E402
from rclpy.qos import QoSProfile  # noqa: E402
from rclpy.qos import ReliabilityPolicy  # noqa: E402
from sensor_msgs.msg import Imu  # noqa: E402
from sensor_msgs.msg import NavSatFix  # noqa: E402
from std_srvs.srv import SetBool  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402
from tether_msgs.msg import UavState  # noqa: E402
from tether_msgs.srv import SetMode  # noqa: E402
from tether_msgs.srv import Takeoff  # noqa: E402

from mavlink_peer_double import ArduCopterPeerDouble  # noqa: E402
from tether_common.qos import COMMAND  # noqa: E402
from tether_common.qos import LATCHED  # noqa: E402
from tether_common.qos import SENSOR  # noqa: E402
from test_uav_bridge_peer import wait_until  # noqa: E402

ORIGIN = (1.0, 2.0, 0.5)


def _start_bridge(*params, domain):
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain))
    args = [arg for param in params for arg in ('-p', param)]
    bridge = Path(get_package_prefix('uav_bridge')) / 'lib' / 'uav_bridge' / 'mavlink_bridge'
    return subprocess.Popen([str(bridge), '--ros-args', *args], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


SERVICES = {'/uav/set_mode': SetMode, '/uav/arm': SetBool, '/uav/takeoff': Takeoff, '/uav/land': Trigger}
ROSOUT = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class Probe:
    """A node recording the bridge's topics and calling its services, spun in a thread.

    Its service clients are made first, before any of its readers. ``service_is_ready`` says only that a client has
    matched the server; the answer goes out only once the server has matched the client's response reader too
    (Fast DDS waits 100 ms for that, then logs 'failed to send response (timeout)' and drops it). A participant
    announces its readers in order, so a message from the server's node on a reader made after the clients (its log
    on /rosout, or /uav/state, which the UAV node offering the services publishes) shows that the server has matched
    their response readers: :meth:`call` waits for one.
    """

    def __init__(self) -> None:
        self.node = rclpy.create_node('bridge_probe')
        self.clients = {name: self.node.create_client(kind, name) for name, kind in SERVICES.items()}
        self.got = {name: [] for name in ('state', 'pose', 'twist', 'imu', 'global', 'log')}
        for name, kind, topic, qos in [('state', UavState, '/uav/state', LATCHED),
                                       ('pose', PoseStamped, '/uav/pose', SENSOR),
                                       ('twist', TwistStamped, '/uav/twist', SENSOR),
                                       ('imu', Imu, '/uav/imu', SENSOR),
                                       ('global', NavSatFix, '/uav/global', SENSOR),
                                       ('log', Log, '/rosout', ROSOUT)]:
            self.node.create_subscription(kind, topic, self.got[name].append, qos)
        self.setpoint = self.node.create_publisher(PoseStamped, '/uav/setpoint', COMMAND)
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def call(self, name, request, timeout=60.0):
        """The service's answer, asked once the server has matched this probe's clients (see the class)."""
        client = self.clients[name]
        wait_until(client.service_is_ready, what=f'service {name}')
        wait_until(lambda: self._servers(name), what=f'the node offering {name}')
        servers = self._servers(name)
        wait_until(lambda: self.got['state'] or any(log.name in servers for log in self.got['log']),
                   what=f'a message from {servers[0]}, the server of {name}')
        future = client.call_async(request)
        wait_until(future.done, timeout=timeout, what=f'answer of {name}')
        return future.result()

    def _servers(self, service):
        """The names of the nodes offering ``service``, as this probe's graph knows them so far."""
        return [name for name, namespace in self.node.get_node_names_and_namespaces()
                if any(offered == service for offered, _ in
                       self.node.get_service_names_and_types_by_node(name, namespace))]

    def state(self):
        return self.got['state'][-1] if self.got['state'] else None

    def close(self):
        self.executor.shutdown()
        self.thread.join(timeout=30)
        self.node.destroy_node()


@pytest.fixture
def ros_domain(ros_domain):
    """The test's reserved ROS domain (the suite's fixture) with rclpy's default context started in it."""
    rclpy.init()
    yield ros_domain
    rclpy.shutdown()


def test_bridge_node_flies_the_double(ros_domain):
    peer = ArduCopterPeerDouble(speedup=5.0, ekf_delay=30.0).start()     # EKF ready 6 s of wall after connect
    process = _start_bridge(f'url:=tcp:127.0.0.1:{peer.port}', f'origin:={list(ORIGIN)}', 'pose_rate:=20.0',
                            'imu_rate:=20.0', 'global_rate:=5.0', 'link_timeout:=1.0', 'status_period:=0.2',
                            domain=ros_domain)
    probe = Probe()
    try:
        wait_until(lambda: probe.state() is not None and probe.state().position_ready, timeout=60,
                   what='position estimate on /uav/state')
        assert any('no LOCAL_POSITION_NED' in s.waiting_for for s in probe.got['state'])
        wait_until(lambda: probe.got['pose'] and probe.got['imu'] and probe.got['twist'], what='telemetry')
        assert probe.got['pose'][-1].header.frame_id == 'world'
        assert probe.got['twist'][-1].header.frame_id == 'world'
        assert probe.got['imu'][-1].header.frame_id == 'uav'
        assert probe.got['imu'][-1].linear_acceleration.z == pytest.approx(9.80665, abs=1e-4)   # FLU, level
        assert probe.got['global'][0].status.status == -1                # lat = lon = 0 before the EKF uses GPS
        wait_until(lambda: probe.got['global'][-1].status.status == 0, what='a global fix')
        assert probe.got['global'][-1].latitude == pytest.approx(-35.363262, abs=1e-6)
        z0 = probe.got['pose'][-1].pose.position.z
        assert z0 == pytest.approx(ORIGIN[2], abs=1e-6)
        wait_until(lambda: peer.sim_time() > peer.rc_mode_switch, what='the RC mode switch')
        assert probe.call('/uav/set_mode', SetMode.Request(mode='GUIDED')).success
        arm = probe.call('/uav/arm', SetBool.Request(data=True))
        assert arm.success, arm.message
        takeoff = probe.call('/uav/takeoff', Takeoff.Request(altitude=10.0))
        assert takeoff.success, takeoff.message
        wait_until(lambda: probe.got['pose'][-1].pose.position.z > ORIGIN[2] + 9.9, what='10 m up')
        assert probe.state().ready and probe.state().armed and probe.state().mode == 'GUIDED'
        setpoint = PoseStamped()
        setpoint.header.frame_id = 'world'
        setpoint.pose.position.x, setpoint.pose.position.y, setpoint.pose.position.z = (
            ORIGIN[0] + 5.0, ORIGIN[1] + 10.0, ORIGIN[2] + 15.0)
        setpoint.pose.orientation.w = 1.0            # facing ENU x: east, NED heading +90 deg
        probe.setpoint.publish(setpoint)
        wait_until(lambda: abs(probe.got['pose'][-1].pose.position.z - setpoint.pose.position.z) < 0.05
                   and abs(probe.got['pose'][-1].pose.position.y - setpoint.pose.position.y) < 0.05,
                   what='the setpoint in world')
        p = probe.got['pose'][-1].pose.position
        assert (p.x, p.y) == pytest.approx((setpoint.pose.position.x, setpoint.pose.position.y), abs=0.05)
        assert peer.snapshot()['position'] == pytest.approx([10.0, 5.0, -15.0], abs=0.05)   # NED at the double
        wait_until(lambda: abs(peer.attitude[2] - math.pi / 2) < 0.01, what='the heading')
        land = probe.call('/uav/land', Trigger.Request())
        assert land.success, land.message
        wait_until(lambda: not probe.state().armed, timeout=60, what='landed and disarmed')
        # a late subscriber gets the latest state at once (transient local)
        late = []
        probe.node.create_subscription(UavState, '/uav/state', late.append, LATCHED)
        wait_until(lambda: late, what='the latched state')
        assert late[0].mode == 'LAND'
        refused = probe.call('/uav/set_mode', SetMode.Request(mode='NOSUCHMODE'))
        assert not refused.success and 'unknown mode' in refused.message
    finally:
        probe.close()
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=20)
        peer.close()
    assert process.returncode == 0, err
    assert 'Traceback' not in err


def test_bad_url_exits_2_with_one_line(ros_domain):
    process = _start_bridge('url:=serial:/dev/ttyS0', domain=ros_domain)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 2
    assert "link URL 'serial:/dev/ttyS0'" in err
    assert 'Traceback' not in err


def test_command_topic_without_the_lockstep_exits_2_with_one_line(ros_domain):
    """/uav/command is a lockstep input: a bridge on an autopilot's own clock refuses it in one line."""
    process = _start_bridge('command_rate:=10.0', domain=ros_domain)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 2 and 'Traceback' not in err
    assert err.strip().splitlines() == ['mavlink_bridge: error: parameter command_rate: /uav/command is a lockstep '
                                        'input, taken only with lockstep_input (SITL on the JSON physics); 0 for '
                                        'services']


def test_commanded_by_the_mission_the_services_refuse_at_once(ros_domain):
    """With command_rate the mission's /uav/command flies the autopilot: a service call by hand is refused at once,
    naming the topic, instead of waiting for a tick (the node spins single-threaded then).
    """
    process = _start_bridge('url:=tcp:127.0.0.1:9', 'lockstep_input:=/uav/pose', 'command_rate:=10.0',
                            domain=ros_domain)
    probe = Probe()
    try:
        answer = probe.call('/uav/arm', SetBool.Request(data=True), timeout=30.0)
    finally:
        probe.close()
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=30)
    assert not answer.success
    assert answer.message == 'the mission commands this UAV on /uav/command (command_rate); the services are off'
    assert process.returncode == 0 and 'Traceback' not in err, err
