"""SimTimer runs every elapsed tick, in order, with the tick's own sim time."""

from __future__ import annotations

import time

import domain_coordinator
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock

from tether_common.sim_timer import SimTimer


@pytest.fixture
def context(monkeypatch):
    monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    with domain_coordinator.domain_id() as domain:
        monkeypatch.setenv('ROS_DOMAIN_ID', str(domain))
        ctx = rclpy.Context()
        rclpy.init(context=ctx)
        yield ctx
        rclpy.shutdown(context=ctx)


def test_jumps_of_sim_time_run_every_missed_tick(context):
    node = Node('timed', context=context, parameter_overrides=[Parameter('use_sim_time', value=True)])
    source = Node('clock_source', context=context)
    publisher = source.create_publisher(Clock, '/clock', 10)
    ticks = []
    SimTimer(node, 0.02, lambda t: ticks.append(t.nanoseconds))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    executor.add_node(source)
    deadline = time.monotonic() + 10
    while publisher.get_subscription_count() < 1 and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    for sim_time in (0.1, 0.25):
        message = Clock()
        message.clock.sec, message.clock.nanosec = 0, int(sim_time * 1e9)
        publisher.publish(message)
        end = time.monotonic() + 1.0
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.02)
    assert ticks == [20_000_000 * k for k in range(1, 13)]
    node.destroy_node()
    source.destroy_node()


def test_period_must_be_positive(context):
    node = Node('timed', context=context)
    with pytest.raises(ValueError, match='period must be positive'):
        SimTimer(node, 0.0, lambda t: None)
    node.destroy_node()
