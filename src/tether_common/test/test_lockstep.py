"""Lockstep: ticks select inputs by stamp, wait for the message they select, ack, and refuse bad stamps."""

from __future__ import annotations

import time

import numpy as np
import pytest
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from tether_msgs.msg import LockstepAck

from tether_common.lockstep import ACK_TOPIC
from tether_common.lockstep import callback_cpu
from tether_common import cdr
from tether_common.lockstep import GroupPublisher
from tether_common.lockstep import JOIN_SETTLE
from tether_common.lockstep import RECORDER_READY_VARIABLE
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import LockstepError
from tether_common.lockstep import _Stream
from tether_common.lockstep import link_in_process
from tether_common.lockstep import stamp_ns
from tether_common.node_main import make_executor
from tether_common.qos import LOCKSTEP_ACK_READER
from tether_common.qos import STATE

MS = 1_000_000


def _point(time_ns: int, value: float) -> PointStamped:
    msg = PointStamped()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(time_ns, 1_000_000_000)
    msg.point.x = value
    return msg


def test_stream_selects_latest_at_or_before_bound_and_knows_what_is_due():
    stream = _Stream('/in', PointStamped, 20 * MS)
    assert stream.ready(19 * MS) and stream.select(19 * MS) is None  # the producer's first stamp is 20 ms
    assert not stream.ready(20 * MS)
    stream.add(_point(20 * MS, 1.0))
    stream.add(_point(40 * MS, 2.0))
    assert stream.ready(59 * MS) and stream.select(59 * MS).point.x == 2.0
    assert stream.select(39 * MS).point.x == 1.0
    assert not stream.ready(60 * MS)
    stream.prune(45 * MS)
    assert [stamp for stamp, _ in stream.messages] == [40 * MS]
    with pytest.raises(LockstepError, match='not a multiple of the declared producer period'):
        stream.add(_point(50 * MS, 3.0))
    with pytest.raises(LockstepError, match='arrived after'):
        stream.add(_point(40 * MS, 3.0))


def _spin_until(executor, condition, timeout=10.0):
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.02)
    return condition()


def test_ticks_wait_for_the_input_they_select_and_ack(ros_context):
    node = Node('stepped', context=ros_context, parameter_overrides=[Parameter('use_sim_time', value=True)])
    source = Node('source', context=ros_context)
    clock = source.create_publisher(Clock, '/clock', STATE)
    inputs = source.create_publisher(PointStamped, '/in', STATE)
    acks = []
    source.create_subscription(LockstepAck, ACK_TOPIC, lambda msg: acks.append(stamp_ns(msg.done)),
                               LOCKSTEP_ACK_READER)
    ticks = []
    lockstep = Lockstep(node)
    lockstep.every(0.01, lambda tick: ticks.append((tick.time_ns, tick.inputs['/in'])),
                   inputs=[Input('/in', PointStamped, period=0.02, delay=0.0)])
    executor = make_executor(ros_context)
    executor.add_node(node)
    executor.add_node(source)
    assert _spin_until(executor, lambda: acks == [0])  # joined once /in has a publisher
    assert _spin_until(executor, lambda: clock.get_subscription_count() >= 2)

    def publish_clock(time_ns):
        message = Clock()
        message.clock.sec, message.clock.nanosec = divmod(time_ns, 1_000_000_000)
        clock.publish(message)

    publish_clock(50 * MS)
    assert _spin_until(executor, lambda: len(ticks) == 1, timeout=2.0)
    time.sleep(0.2)
    executor.spin_once(timeout_sec=0.1)
    assert [t for t, _ in ticks] == [10 * MS]  # tick 20 ms waits for the input stamped 20 ms
    assert acks == [0]
    inputs.publish(_point(20 * MS, 1.0))
    inputs.publish(_point(40 * MS, 2.0))
    assert _spin_until(executor, lambda: acks[-1] == 50 * MS)
    assert [t for t, _ in ticks] == [10 * MS, 20 * MS, 30 * MS, 40 * MS, 50 * MS]
    assert [None if m is None else m.point.x for _, m in ticks] == [None, 1.0, 1.0, 2.0, 2.0]
    node.destroy_node()
    source.destroy_node()


def test_a_delayed_input_cycle_needs_no_message_of_the_same_tick(ros_context):
    node = Node('delayed', context=ros_context, parameter_overrides=[Parameter('use_sim_time', value=True)])
    source = Node('source', context=ros_context)
    clock = source.create_publisher(Clock, '/clock', STATE)
    inputs = source.create_publisher(PointStamped, '/in', STATE)
    ticks = []
    lockstep = Lockstep(node)
    lockstep.every(0.01, lambda tick: ticks.append(tick.inputs['/in']),
                   inputs=[Input('/in', PointStamped, period=0.01, delay=0.01)])
    executor = make_executor(ros_context)
    executor.add_node(node)
    executor.add_node(source)
    assert _spin_until(executor, lambda: clock.get_subscription_count() >= 2 and inputs.get_subscription_count() >= 1)
    inputs.publish(_point(10 * MS, 1.0))
    message = Clock()
    message.clock.nanosec = 20 * MS
    clock.publish(message)
    assert _spin_until(executor, lambda: len(ticks) == 2)
    assert ticks[0] is None and ticks[1].point.x == 1.0
    node.destroy_node()
    source.destroy_node()


def test_an_input_must_be_stamped(ros_context):
    from std_msgs.msg import Float64
    node = Node('unstamped', context=ros_context)
    with pytest.raises(ValueError, match='has no header'):
        Lockstep(node).every(0.01, lambda tick: None, inputs=[Input('/x', Float64, period=0.01)])
    with pytest.raises(ValueError, match='period must be positive'):
        Lockstep(node).every(0.0, lambda tick: None)
    node.destroy_node()


def test_a_node_joins_only_once_the_recorder_is_ready(ros_context, tmp_path, monkeypatch):
    """The recorder subscribes to a node's topics by polling the graph: a node that joined before that could
    publish its first ticks before its publisher has matched the recorder, and the bag would miss them.
    """
    ready_file = tmp_path / 'recorder.ready'
    monkeypatch.setenv(RECORDER_READY_VARIABLE, str(ready_file))
    node = Node('waiting', context=ros_context)
    source = Node('source', context=ros_context)
    acks = []
    source.create_subscription(LockstepAck, ACK_TOPIC, lambda msg: acks.append(stamp_ns(msg.done)),
                               LOCKSTEP_ACK_READER)
    Lockstep(node)
    executor = make_executor(ros_context)
    executor.add_node(node)
    executor.add_node(source)
    assert not _spin_until(executor, lambda: acks, timeout=2.0 + JOIN_SETTLE)
    ready_file.write_text('')
    assert _spin_until(executor, lambda: acks == [0])
    node.destroy_node()
    source.destroy_node()


def test_nodes_of_one_process_hand_messages_over_and_keep_their_readers_in_the_graph(ros_context):
    """link_in_process: a lockstep input published in the process takes each message as its own copy, so the
    producer may refill one object; a plain subscription gets it at once, inside the publish; the inputs' DDS
    readers stay in the graph, matched, best effort, and take nothing.
    """
    producer = Node('producer', context=ros_context)
    consumer = Node('consumer', context=ros_context)
    clock = producer.create_publisher(Clock, '/clock', STATE)
    inputs = producer.create_publisher(PointStamped, '/in', STATE)
    side = producer.create_publisher(PointStamped, '/side', STATE)
    ticks, side_values = [], []
    consumer.create_subscription(PointStamped, '/side', lambda msg: side_values.append(msg.point.x), STATE)
    lockstep = Lockstep(consumer)
    lockstep.every(0.01, lambda tick: ticks.append(tick.inputs['/in']),
                   inputs=[Input('/in', PointStamped, period=0.01, delay=0.01)])
    links = link_in_process([producer, consumer])
    # the lockstep's /clock subscription is a plain one: linked too
    assert all(isinstance(publisher, GroupPublisher) for publisher in (inputs, side, clock))
    assert inputs.serialize is cdr.serializer(PointStamped)  # sent over DDS as tether_common.cdr's bytes
    assert consumer.count_subscribers('/in') == 1 and consumer.count_subscribers('/side') == 1
    assert not any(s.topic_name in ('/in', '/side') for s in consumer.subscriptions)  # nothing for the executor
    assert {info.qos_profile.reliability for topic in ('/in', '/side')
            for info in consumer.get_subscriptions_info_by_topic(topic)} == {ReliabilityPolicy.BEST_EFFORT}
    executor = make_executor(ros_context)
    executor.add_node(producer)
    executor.add_node(consumer)
    assert _spin_until(executor, lambda: inputs.get_subscription_count() == 1 and side.get_subscription_count() == 1)
    message = _point(10 * MS, 1.0)
    message.point.y = np.float64(0.5)
    inputs.publish(message)
    side.publish(message)
    assert side_values == [1.0]  # delivered inside the publish, before any spin
    message.header.stamp.nanosec, message.point.x = 20 * MS, 2.0  # the producer refills its one object
    inputs.publish(message)
    tick_clock = Clock()
    tick_clock.clock.nanosec = 30 * MS
    clock.publish(tick_clock)  # also handed over: the ticks run inside this publish
    assert [None if m is None else (stamp_ns(m.header.stamp), m.point.x) for m in ticks] == [
        None, (10 * MS, 1.0), (20 * MS, 2.0)]
    assert type(ticks[1].point.y) is float and ticks[1] is not ticks[2]
    links.close()
    producer.destroy_node()
    consumer.destroy_node()


def test_lockstep_nodes_of_one_process_share_one_clock_subscription(ros_context):
    """link_in_process: one /clock subscription advances every lockstep node of the process; the
    others' /clock readers stay in the graph, matched, and take nothing.
    """
    master = Node('time_master', context=ros_context)  # not linked: its /clock arrives over DDS
    clock = master.create_publisher(Clock, '/clock', STATE)
    nodes = [Node(name, context=ros_context) for name in ('first', 'second', 'third')]
    ticks = {node.get_name(): [] for node in nodes}
    for node in nodes:
        Lockstep(node).every(0.01, lambda tick, name=node.get_name(): ticks[name].append(tick.seconds))
    links = link_in_process(nodes)
    assert [sum(s.topic_name == '/clock' for s in node.subscriptions) for node in nodes] == [1, 0, 0]
    executor = make_executor(ros_context)
    for node in (master, *nodes):
        executor.add_node(node)
    assert _spin_until(executor, lambda: clock.get_subscription_count() == 3)
    assert master.count_subscribers('/clock') == 3
    tick_clock = Clock()
    tick_clock.clock.nanosec = 20 * MS
    clock.publish(tick_clock)
    assert _spin_until(executor, lambda: all(len(seconds) == 2 for seconds in ticks.values()))
    assert ticks == {name: [0.01, 0.02] for name in ticks}
    links.close()
    for node in (master, *nodes):
        node.destroy_node()


def test_group_publishers_write_to_dds_only_while_a_reader_outside_is_matched(ros_context):
    """GroupPublisher: with only the process's idle readers matched, a message is handed over but not written
    to DDS, so a reader from outside that joins later does not get it (a transient-local reader would, from the
    writer's history, had it been written); once that reader has matched, each message is written.
    """
    producer = Node('producer', context=ros_context)
    consumer = Node('consumer', context=ros_context)
    handed = []
    consumer.create_subscription(PointStamped, '/side', lambda msg: handed.append(msg.point.x), STATE)
    side = producer.create_publisher(PointStamped, '/side', STATE)
    links = link_in_process([producer, consumer])
    assert side.idle_readers == 1
    executor = make_executor(ros_context)
    executor.add_node(producer)
    executor.add_node(consumer)
    assert _spin_until(executor, lambda: side.get_subscription_count() == 1)
    for k in (1, 2, 3):
        side.publish(_point(k * 10 * MS, float(k)))
    late = Node('late_reader', context=ros_context)  # not linked: a reader outside the group
    received = []
    late.create_subscription(PointStamped, '/side', lambda msg: received.append(msg.point.x), STATE)
    executor.add_node(late)
    assert _spin_until(executor, lambda: side.get_subscription_count() == 2)
    side.publish(_point(40 * MS, 4.0))
    assert _spin_until(executor, lambda: received)
    _spin_until(executor, lambda: False, timeout=0.3)  # a history, had it been written, arrives with it
    assert received == [4.0] and handed == [1.0, 2.0, 3.0, 4.0]
    links.close()
    for node in (producer, consumer, late):
        node.destroy_node()


def test_callback_cpu_gives_each_node_the_thread_cpu_of_its_ticks(ros_context):
    """callback_cpu: the scheduler charges each node of the process the thread CPU of its own ticks: a node that
    spends 5 ms of CPU a tick is charged that, one beside it that does nothing next to nothing.
    """
    master = Node('time_master', context=ros_context)
    clock = master.create_publisher(Clock, '/clock', STATE)
    busy, light = Node('busy', context=ros_context), Node('light', context=ros_context)

    def spin_5ms(tick):
        start = time.thread_time()
        while time.thread_time() - start < 0.005:
            pass
    Lockstep(busy).every(0.01, spin_5ms)
    Lockstep(light).every(0.01, lambda tick: None)
    links = link_in_process([busy, light])
    executor = make_executor(ros_context)
    for node in (master, busy, light):
        executor.add_node(node)
    assert _spin_until(executor, lambda: clock.get_subscription_count() == 2)
    before = callback_cpu()
    tick_clock = Clock()
    tick_clock.clock.nanosec = 40 * MS
    clock.publish(tick_clock)
    assert _spin_until(executor, lambda: callback_cpu()['/busy'] - before['/busy'] >= 0.02)
    after = callback_cpu()
    assert after['/busy'] - before['/busy'] == pytest.approx(0.02, rel=0.25)
    assert after['/light'] - before['/light'] < 0.002
    links.close()
    for node in (master, busy, light):
        node.destroy_node()
