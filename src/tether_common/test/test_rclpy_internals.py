"""Every assumption :mod:`tether_common.rclpy_internals` makes about rclpy's private parts, checked
against the installed rclpy: an upgrade that breaks one fails here, naming it, instead of inside a run.
"""

from __future__ import annotations

import time

import pytest
import rclpy
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from rclpy.publisher import Publisher

from tether_common import rclpy_internals
from tether_common.node_main import make_executor
from tether_common.qos import IDLE_READER
from tether_common.qos import STATE


class _Counting(Publisher):
    """A publisher subclass as the lockstep makes one: instance attributes and ``publish`` only."""

    sent: list

    def publish(self, msg) -> None:
        self.sent.append(msg)
        super().publish(msg)


def _spin_until(executor, done, timeout: float = 10.0) -> bool:
    """Spin until ``done()`` (DDS matching is asynchronous); False when it never is."""
    end = time.monotonic() + timeout
    while not done() and time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    return bool(done())


def test_rcl_error_is_an_exception_that_init_raises_for_arguments_rcl_refuses(ros_domain) -> None:
    assert issubclass(rclpy_internals.RCLError, Exception), 'rclpy_implementation.RCLError is no longer an exception'
    with pytest.raises(rclpy_internals.RCLError, match='-r'):
        rclpy.init(args=['probe', '--ros-args', '-r'], context=rclpy.Context())


def test_an_idle_reader_is_matched_by_publishers_and_unseen_by_the_node(ros_context) -> None:
    node = Node('idle_probe', context=ros_context)
    publisher = node.create_publisher(PointStamped, '/idle_probe', STATE)
    reader = rclpy_internals.idle_reader(node, PointStamped, '/idle_probe', IDLE_READER)
    executor = make_executor(ros_context)
    executor.add_node(node)
    try:
        assert _spin_until(executor, lambda: publisher.get_subscription_count() == 1), \
            'the idle reader (rclpy_implementation.Subscription) is not matched by the topic\'s publisher'
        assert list(node.subscriptions) == [], 'the idle reader shows among the node\'s subscriptions'
        publisher.publish(PointStamped())
        executor.spin_once(timeout_sec=0.1)               # nothing for the executor to take: no callback exists
    finally:
        reader.destroy_when_not_in_use()
        executor.shutdown()
        node.destroy_node()


def test_a_node_s_publisher_becomes_a_subclass_in_place(ros_context) -> None:
    assert '__slots__' not in vars(Publisher), 'rclpy.publisher.Publisher has __slots__: its class cannot be set'
    node = Node('subclass_probe', context=ros_context)
    plain = node.create_publisher(PointStamped, '/subclass_probe', STATE)
    counting = rclpy_internals.as_subclass(plain, _Counting)
    counting.sent = []
    try:
        assert counting is plain and type(plain) is _Counting
        assert any(p is plain for p in node.publishers), 'node.publishers no longer holds the object the node made'
        msg = PointStamped()
        plain.publish(msg)
        assert counting.sent == [msg]
        with pytest.raises(TypeError, match='not a subclass'):
            rclpy_internals.as_subclass(plain, Publisher)
    finally:
        node.destroy_node()
