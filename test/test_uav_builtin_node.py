"""The mission flying the built-in UAV node over /uav/command (lockstep inputs both ways), against a tether pull."""

from __future__ import annotations


import pytest

rclpy = pytest.importorskip('rclpy')

from geometry_msgs.msg import PoseStamped  # noqa: E402
from geometry_msgs.msg import WrenchStamped  # noqa: E402
from rclpy.clock import Clock as RosClock  # noqa: E402
from rclpy.clock import ClockType  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from std_srvs.srv import SetBool  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402
from tether_msgs.msg import MissionState  # noqa: E402
from tether_msgs.msg import ReelControllerDiagnostics  # noqa: E402
from tether_msgs.msg import ReelState  # noqa: E402
from tether_msgs.srv import Takeoff  # noqa: E402

from tether_bringup.barrier import Barrier  # noqa: E402
from tether_common.lockstep import NODES_VARIABLE  # noqa: E402
from tether_common.lockstep import publishers_matched  # noqa: E402
from tether_common.qos import CLOCK  # noqa: E402
from tether_common.qos import LATCHED  # noqa: E402
from tether_common.qos import STATE  # noqa: E402
from test_uav_bridge_node import Probe  # noqa: E402
from test_uav_bridge_node import ros_domain  # noqa: E402,F401 - fixture
from test_uav_bridge_peer import wait_until  # noqa: E402
from test_uav_mission_node import _start  # noqa: E402
from test_uav_mission_node import assert_clean_exits  # noqa: E402
from test_uav_mission_node import stop_nodes  # noqa: E402


def members_env(*names: str) -> dict:
    """The environment that makes the lockstep nodes ``names`` (and the test's probe) join together, as in a run."""
    return {NODES_VARIABLE: ','.join(('bridge_probe',) + names)}


def publish_clock_wrench_and_reel(probe, pull: WrenchStamped, reel: ReelState, members: list[str]) -> None:
    """Be the time master of ``members`` (node names): advance ``/clock`` by 10 ms once each has acked the
    current value, at most at wall speed, and, as the plant and the reel would, publish a wrench, a reel
    state and reel diagnostics stamped with each step.

    The built-in UAV takes ``/tether/uav_wrench`` as a lockstep input (one step late), the
    mission ``/reel/state`` and ``/reel/diagnostics`` (no delay), so every step needs them;
    ``pull`` is the force sent (zero until the test sets it), ``reel`` the reel state. The
    clock starts only once every member has joined, so no node misses the first commands
    of another, whenever each process gets to start, and only once the probe's publishers have
    matched every subscription of their topics.
    """
    clock = probe.node.create_publisher(Clock, '/clock', CLOCK)
    wrench = probe.node.create_publisher(WrenchStamped, '/tether/uav_wrench', STATE)
    reel_state = probe.node.create_publisher(ReelState, '/reel/state', STATE)
    diagnostics = probe.node.create_publisher(ReelControllerDiagnostics, '/reel/diagnostics', STATE)
    barrier = Barrier(probe.node, ['/' + name for name in members])
    reasons = ReelControllerDiagnostics()
    step = [0]

    def matched() -> bool:
        """The probe's publishers have matched every subscription of their topics (a node's subscription
        matching them does not mean they have matched it; a message published before is lost to it).
        """
        return clock.get_subscription_count() >= len(members) and publishers_matched(
            probe.node, (wrench, reel_state, diagnostics))

    def tick() -> None:
        if not barrier.reached(step[0] * 10_000_000) or (step[0] == 0 and not matched()):
            return
        step[0] += 1
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = divmod(step[0] * 10_000_000, 1_000_000_000)
        pull.header.stamp = reel.header.stamp = reasons.header.stamp = msg.clock
        reasons.safety_trip = 'test trip' if reel.mode == ReelState.MODE_FAULT else ''
        wrench.publish(pull)
        reel_state.publish(reel)
        diagnostics.publish(reasons)
        clock.publish(msg)
    probe.node.create_timer(0.01, tick, clock=RosClock(clock_type=ClockType.STEADY_TIME))


def test_mission_flies_the_builtin_uav_against_a_tether_pull(ros_domain):  # noqa: F811
    processes = [
        _start('uav_bridge.builtin.node', 'start:=[0.0, 0.0, 0.3]', 'tether_force:=topic', 'command_rate:=10.0',
               domain=ros_domain, env=members_env('builtin_uav', 'mission')),
        _start('uav_bridge.mission.node', 'altitude:=5.0', 'radial:=2.5', 'retry_period:=0.5', 'reel_rate:=100.0',
               'return_speed:=1.0', 'return_height:=2.0', domain=ros_domain, env=members_env('builtin_uav', 'mission'))]
    probe = Probe()
    pull = WrenchStamped()
    pull.header.frame_id = 'world'
    reel = ReelState()
    publish_clock_wrench_and_reel(probe, pull, reel, ['builtin_uav', 'mission'])
    phases = []
    probe.node.create_subscription(MissionState, '/mission/state', phases.append, LATCHED)
    try:
        wait_until(lambda: probe.state() is not None, timeout=60, what='/uav/state')
        assert probe.state().position_ready and probe.state().connected
        wait_until(lambda: phases and phases[-1].phase == 'hold', timeout=60, what='the hold phase')
        # the UAV's state stamped 0.1 s is the mission's first step's input: it arms at once
        assert [p.phase for p in phases][:4] == ['arm', 'takeoff', 'climb', 'hold']
        pull.wrench.force.x, pull.wrench.force.z = -2.0, -3.0      # toward the reel and down
        wait_until(lambda: probe.got['pose'] and abs(probe.got['pose'][-1].pose.position.x - 2.5) < 0.03
                   and abs(probe.got['pose'][-1].pose.position.z - 5.0) < 0.03
                   and abs(probe.got['twist'][-1].twist.linear.x) < 0.01, timeout=60, what='the station')
        assert probe.got['pose'][-1].header.frame_id == 'world' and probe.got['imu'][-1].header.frame_id == 'uav'
        assert probe.state().ready and probe.state().mode == 'GUIDED'
        reel.mode = ReelState.MODE_FAULT
        wait_until(lambda: phases[-1].phase == 'landed', timeout=60, what='landed after the reel trip')
        assert phases[-1].aborted and 'test trip' in phases[-1].reason
        assert [p.phase for p in phases][-3:] == ['return', 'land', 'landed']     # over its pad, not where it was
        position = probe.got['pose'][-1].pose.position
        assert position.z == pytest.approx(0.3) and abs(position.x) < 0.5 and abs(position.y) < 0.5
    finally:
        probe.close()
        stopped = stop_nodes(processes)
    assert_clean_exits(stopped)


def test_a_uav_that_does_not_take_the_command_topic_stops_the_mission_with_one_line(ros_domain):  # noqa: F811
    """The built-in UAV without command_rate serves only its services: the mission's first request is not answered
    on /uav/state within 1 s of sim time, and the mission ends naming the mismatch instead of waiting for ever.
    """
    uav = _start('uav_bridge.builtin.node', 'start:=[0.0, 0.0, 0.3]', 'tether_force:=topic', domain=ros_domain,
                 env=members_env('builtin_uav', 'mission'))
    mission = _start('uav_bridge.mission.node', 'reel_rate:=100.0', domain=ros_domain,
                     env=members_env('builtin_uav', 'mission'))
    probe = Probe()
    publish_clock_wrench_and_reel(probe, WrenchStamped(), ReelState(), ['builtin_uav', 'mission'])
    try:
        _, err = mission.communicate(timeout=120)
    finally:
        probe.close()
        stopped = stop_nodes([uav])
    assert mission.returncode == 2 and 'Traceback' not in err, err
    assert 'error: /uav/state has not answered the arm request of /uav/command 1 within 1 s: run the built-in UAV, or ' \
           'mavlink_bridge, with command_rate 10' in err
    assert_clean_exits(stopped)


def test_by_hand_the_services_and_the_setpoint_topic_fly_it(ros_domain):  # noqa: F811
    """Without a mission (command_rate 0) the built-in UAV answers the bridge's services and follows /uav/setpoint,
    as a user calling them with ``ros2 service call`` and ``ros2 topic pub`` would.
    """
    uav = _start('uav_bridge.builtin.node', 'start:=[0.0, 0.0, 0.3]', domain=ros_domain,
                 env=members_env('builtin_uav'))
    probe = Probe()
    publish_clock_wrench_and_reel(probe, WrenchStamped(), ReelState(), ['builtin_uav'])
    try:
        assert probe.call('/uav/arm', SetBool.Request(data=True)).success
        assert probe.call('/uav/takeoff', Takeoff.Request(altitude=2.0)).success
        wait_until(lambda: probe.state() is not None and probe.state().armed and probe.got['pose']
                   and probe.got['pose'][-1].pose.position.z > 2.0, timeout=60, what='the climb')
        target = PoseStamped()
        target.header.frame_id = 'world'
        target.pose.position.x, target.pose.position.z = 1.0, 2.3
        probe.setpoint.publish(target)
        wait_until(lambda: abs(probe.got['pose'][-1].pose.position.x - 1.0) < 0.05, timeout=60, what='the setpoint')
        assert probe.call('/uav/land', Trigger.Request()).success
        wait_until(lambda: not probe.state().armed, timeout=60, what='landed and disarmed')
        assert probe.state().mode == 'LAND' and probe.state().command_sequence == 0
        assert probe.got['pose'][-1].pose.position.z == pytest.approx(0.3)
    finally:
        probe.close()
        stopped = stop_nodes([uav])
    assert_clean_exits(stopped)
