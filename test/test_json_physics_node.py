"""The json_physics node in lockstep: SITL (the test double) runs only as far as the graph's /clock."""

from __future__ import annotations

import signal
import threading
import time

import numpy as np

import pytest

rclpy = pytest.importorskip('rclpy')

from builtin_interfaces.msg import Time  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from geometry_msgs.msg import WrenchStamped  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from tether_msgs.msg import TetherState  # noqa: E402

from json_sitl_peer_double import SitlJsonPeerDouble  # noqa: E402
from sitl_process import claim_instance  # noqa: E402
from tether_common.qos import CLOCK  # noqa: E402
from tether_common.qos import STATE  # noqa: E402
from tether_models.constants import GRAVITY  # noqa: E402
from test_uav_bridge_node import Probe  # noqa: E402
from test_uav_bridge_node import ros_domain  # noqa: E402,F401 - fixture
from test_uav_bridge_peer import wait_until  # noqa: E402
from test_uav_mission_node import _start  # noqa: E402
from uav_bridge.json_physics.protocol import physics_port  # noqa: E402

FRAME_RATE = 800


class SitlThread:
    """The SITL double sending frames as fast as it gets replies, resending after silence."""

    def __init__(self, port: int) -> None:
        self.peer = SitlJsonPeerDouble(port, frame_rate=FRAME_RATE, resend_after=0.1)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        while not self.stop.is_set():
            self.peer.send()
            while not self.stop.is_set() and self.peer.receive() is None:
                self.peer.log.resends += 1
                self.peer.send()

    def close(self) -> None:
        self.stop.set()
        self.thread.join(5)
        self.peer.close()


def test_sitl_advances_only_with_the_graph_clock(ros_domain):  # noqa: F811
    instance, lock = claim_instance()
    process = _start('uav_bridge.json_physics.node', f'instance:={instance}', 'wrench_rate:=0.0',
                     'start:=[1.0, 2.0, 0.5]', domain=ros_domain)
    probe = Probe()
    clock = probe.node.create_publisher(Clock, '/clock', CLOCK)
    sitl = SitlThread(physics_port(instance))

    def advance(seconds: float, until, what: str) -> None:
        """Publish /clock = ``seconds`` (again and again, until it is heard) until ``until()``."""
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = divmod(round(seconds * 1e9), 1_000_000_000)

        def heard() -> bool:
            clock.publish(msg)
            return until()
        wait_until(heard, timeout=60, what=what)

    try:
        wait_until(lambda: sitl.peer.log.resends > 0, timeout=60, what='SITL resending while the clock stands')
        assert sitl.peer.frame_count == 0                       # no tick yet: no reply
        advance(0.5, lambda: probe.got['imu'] and probe.got['imu'][-1].header.stamp.nanosec == 500_000_000,
                'the tick at 0.5 s')
        wait_until(lambda: sitl.peer.log.resends > 3, timeout=60, what='SITL waiting again')
        # SITL stopped where the clock stopped (a reply that raced a resend may count once more in SITL)
        assert 0.5 * FRAME_RATE <= sitl.peer.frame_count <= 0.5 * FRAME_RATE + sitl.peer.log.repeated
        assert sitl.peer.log.clock == pytest.approx(0.5)        # and its clock is the graph's sim time
        stamps = [msg.header.stamp.nanosec for msg in probe.got['pose']]       # sensor QoS: some may drop
        assert stamps[-1] == 500_000_000 and all(s % 10_000_000 == 0 for s in stamps)
        assert all(b > a for a, b in zip(stamps, stamps[1:]))                 # one pose per tick, in order
        imu = probe.got['imu'][-1]
        assert imu.header.frame_id == 'uav' and imu.linear_acceleration.z == pytest.approx(GRAVITY)   # FLU, at rest
        pose = probe.got['pose'][-1].pose.position
        assert (pose.x, pose.y, pose.z) == pytest.approx((1.0, 2.0, 0.5))
        sitl.peer.pwm[:4] = [1000] * 4
        advance(1.0, lambda: sitl.peer.log.clock == pytest.approx(1.0), 'SITL at 1.0 s')
        assert FRAME_RATE <= sitl.peer.frame_count <= FRAME_RATE + sitl.peer.log.repeated
    finally:
        sitl.close()
        probe.close()
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=20)
        lock.close()
        print(err[-3000:])
    assert process.returncode == 0 and 'Traceback' not in err, err


def test_straight_line_pulls_toward_the_reel_with_its_weight_and_its_spring_beyond_the_deployed_length(
        ros_domain, lockstep_master):  # noqa: F811
    """``tether_model: straight_line`` (ArduPilot's SIM_Tether, the report's baseline): the force on the UAV points
    at the reel pose, with the line's weight mu |d| g, plus the spring on the stretch beyond the plant's deployed
    length; the UAV rests 8 m from the reel, the deployed length goes from 7.9 m (taut) to 20 m (slack).
    """
    instance, lock = claim_instance()
    process = _start('uav_bridge.json_physics.node', f'instance:={instance}', 'tether_model:=straight_line',
                     'start:=[8.0, 0.0, 0.5]', domain=ros_domain,
                     env=lockstep_master.environment('straight_line_probe', ['/json_physics']))
    sitl = SitlThread(physics_port(instance))
    node = rclpy.create_node('straight_line_probe')
    forces = []
    node.create_subscription(WrenchStamped, '/uav/tether_force', forces.append, STATE)
    publishers = {topic: node.create_publisher(kind, topic, STATE) for topic, kind in
                  (('/tether/uav_wrench', WrenchStamped), ('/tether/state', TetherState),
                   ('/platform/reel_pose', PoseStamped))}
    master = lockstep_master(node, ['/json_physics'], [process])
    wrench, state, reel = WrenchStamped(), TetherState(), PoseStamped()
    reel.pose.position.z = 0.5
    try:
        master.wait_acked(0)
        for step in range(1, 41):
            state.deployed_length = 7.9 if step <= 20 else 20.0
            wrench.header.stamp = state.header.stamp = reel.header.stamp = \
                Time(sec=0, nanosec=step * 10_000_000)
            for topic, msg in (('/tether/uav_wrench', wrench), ('/tether/state', state),
                               ('/platform/reel_pose', reel)):
                publishers[topic].publish(msg)
            master.step_to(step * 10_000_000)
        end = time.monotonic() + 2.0
        while time.monotonic() < end and len(forces) < 40:
            rclpy.spin_once(node, timeout_sec=0.01)
    finally:
        sitl.close()
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=20)
        node.destroy_node()
        lock.close()
    assert process.returncode == 0 and 'Traceback' not in err, err
    by_step = {f.header.stamp.nanosec // 10_000_000: np.array([f.wrench.force.x, f.wrench.force.y,
                                                               f.wrench.force.z]) for f in forces}
    weight = 0.042 * 8.0 * GRAVITY                  # line_density x |d| x g
    # the tick at 0.02 s took the deployed length of the step before (one period late): 0.1 m stretched
    np.testing.assert_allclose(by_step[2], [-(weight + 100.0 * 0.1), 0.0, 0.0], atol=0.05)
    # slack (the length of the step at 0.2 s, seen from 0.21 s on): the weight alone, still toward the reel
    np.testing.assert_allclose(by_step[40], [-weight, 0.0, 0.0], rtol=0.02, atol=0.02)
