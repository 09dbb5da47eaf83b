"""The recorder takes a topic only the node group publishes from the group's recording stream, and a topic
another process publishes too from DDS, each message once, and reads the stream to its end before it
finalizes the bag.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path

import yaml
from ament_index_python.packages import get_package_prefix
from geometry_msgs.msg import PointStamped
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from tether_bringup.bag_reader import read_bag
from tether_common import cdr
from tether_common.qos import STATE
from tether_common.record_stream import StreamWriter
from tether_common.record_stream import open_pipe

NS = 1_000_000_000


def _point(stamp_s: float, x: float) -> PointStamped:
    msg = PointStamped()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(round(stamp_s * NS), NS)
    msg.point.x = x
    return msg


def _spin(executor, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.01)


@contextmanager
def _recorder_and_group(ros_context, tmp_path: Path, node_names: list[str], *parameters: str,
                        expected: list[str] | None = None):
    """The recorder, with the read end of its stream (group ``/group_a``), and the test's nodes on one executor;
    the recorder waits for ``expected`` nodes (default: ``node_names``).

    Yields (recorder process, stream writer, nodes by name, executor); on leaving, the recorder must have
    exited with status 0 (the test stops it), and the nodes are destroyed.
    """
    read_fd, write_fd = open_pipe()
    recorder = subprocess.Popen(
        [str(Path(get_package_prefix('tether_bringup')) / 'lib' / 'tether_bringup' / 'recorder'), '--ros-args',
         '-p', f'bag_directory:={tmp_path / "bag"}', '-p', f'ready_file:={tmp_path / "recorder.ready"}',
         '-p', f'stream_fd:={read_fd}', '-p', "stream_nodes:=['/group_a']", '-p', f'expected_nodes:={expected or node_names}',
         '-p', 'settle_time:=0.3', *(item for parameter in parameters for item in ('-p', parameter))],
        pass_fds=(read_fd,), stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    os.close(read_fd)
    nodes = {name: Node(name, context=ros_context) for name in node_names}
    executor = SingleThreadedExecutor(context=ros_context)
    for node in nodes.values():
        executor.add_node(node)
    try:
        yield recorder, StreamWriter(write_fd), nodes, executor
        output = recorder.communicate(timeout=60)[0].decode()
        assert recorder.returncode == 0, output
    finally:
        if recorder.poll() is None:
            recorder.kill()
        for node in nodes.values():
            node.destroy_node()


def _wait_ready(recorder: subprocess.Popen, ready: Path, executor) -> None:
    deadline = time.monotonic() + 60.0
    while not ready.exists():
        assert recorder.poll() is None, recorder.communicate()[0].decode()
        assert time.monotonic() < deadline, 'the recorder did not get ready within 60 s'
        _spin(executor, 0.05)


def test_group_only_topic_comes_from_the_stream_and_a_shared_one_from_dds(ros_context, tmp_path):
    ready = tmp_path / 'recorder.ready'
    with _recorder_and_group(ros_context, tmp_path, ['group_a', 'outside']) as (recorder, stream, nodes, executor):
        group, outside = nodes['group_a'], nodes['outside']
        group_x = group.create_publisher(PointStamped, '/x', STATE)
        group_m = group.create_publisher(PointStamped, '/m', STATE)
        outside_m = outside.create_publisher(PointStamped, '/m', STATE)
        x_id, m_id = stream.announce('/x', '/group_a'), stream.announce('/m', '/group_a')
        stream.announced()
        serialize = cdr.serializer(PointStamped)
        stream.add(x_id, serialize(_point(1.0, 1.0)))  # before the recorder has decided: held, then written
        stream.flush()
        _wait_ready(recorder, ready, executor)
        _spin(executor, 0.5)
        assert yaml.safe_load(ready.read_text()) == {'/clock': 'dds', '/m': 'dds', '/x': 'stream'}

        group_x.publish(_point(2.0, 77.0))  # over DDS only: the recorder does not subscribe to /x
        group_m.publish(_point(2.0, 2.0))
        outside_m.publish(_point(3.0, 3.0))
        stream.add(m_id, serialize(_point(2.0, 99.0)))  # /m comes from DDS: its stream frames are dropped
        for index in range(2, 500):
            stream.add(x_id, serialize(_point(float(index), float(index))))
        for publisher in (group_m, outside_m):
            assert publisher.wait_for_all_acked(Duration(seconds=30))
        _spin(executor, 0.5)
        stream.close()
        recorder.send_signal(signal.SIGINT)
    bag = read_bag(tmp_path / 'bag')
    assert bag.complete
    x = bag.decoded('/x')
    assert [msg.point.x for _, msg in x] == [1.0] + [float(index) for index in range(2, 500)]
    assert [log_time for log_time, _ in x] == [NS] + [index * NS for index in range(2, 500)]
    assert sorted(msg.point.x for _, msg in bag.decoded('/m')) == [2.0, 3.0]


def test_a_streamed_topic_that_an_outside_node_starts_publishing_is_recorded_from_dds(ros_context, tmp_path):
    ready = tmp_path / 'recorder.ready'
    with _recorder_and_group(ros_context, tmp_path, ['group_a'], expected=['group_a', 'late']) as (
            recorder, stream, nodes, executor):
        group_x = nodes['group_a'].create_publisher(PointStamped, '/x', STATE)
        x_id = stream.announce('/x', '/group_a')
        stream.announced()
        deadline = time.monotonic() + 60.0
        while nodes['group_a'].count_subscribers('/clock') < 1:  # the recorder is up
            assert time.monotonic() < deadline, 'the recorder did not start within 60 s'
            _spin(executor, 0.05)
        _spin(executor, 1.0)  # ten discoveries: the recorder takes /x from the stream
        late = Node('late', context=ros_context)
        executor.add_node(late)
        try:
            late_x = late.create_publisher(PointStamped, '/x', STATE)
            _wait_ready(recorder, ready, executor)
            _spin(executor, 0.5)
            assert yaml.safe_load(ready.read_text()) == {'/clock': 'dds', '/x': 'dds'}
            group_x.publish(_point(2.0, 2.0))
            late_x.publish(_point(3.0, 3.0))
            stream.add(x_id, cdr.serializer(PointStamped)(_point(2.0, 99.0)))
            for publisher in (group_x, late_x):
                assert publisher.wait_for_all_acked(Duration(seconds=30))
            _spin(executor, 0.5)
            stream.close()
            recorder.send_signal(signal.SIGINT)
        finally:
            late.destroy_node()
    assert sorted(msg.point.x for _, msg in read_bag(tmp_path / 'bag').decoded('/x')) == [2.0, 3.0]


def test_interrupted_recorder_reads_the_stream_to_its_end_and_finalizes_the_bag(ros_context, tmp_path):
    """Ctrl-C while messages pour in: the recorder writes every message the group sent before it closed
    the stream, and the bag is complete (an interrupt inside a chunk's write would leave it unreadable).
    """
    ready = tmp_path / 'recorder.ready'
    with _recorder_and_group(ros_context, tmp_path, ['group_a'], 'flush_period:=0.05') as (
            recorder, stream, nodes, executor):
        nodes['group_a'].create_publisher(PointStamped, '/x', STATE)
        x_id = stream.announce('/x', '/group_a')
        stream.announced()
        _wait_ready(recorder, ready, executor)
        serialize = cdr.serializer(PointStamped)
        sent = 0
        start = time.monotonic()
        interrupted = False
        while time.monotonic() - start < 1.5:  # Ctrl-C after 1 s; the group sends on for 0.5 s
            for _ in range(50):
                sent += 1
                stream.add(x_id, serialize(_point(sent * 0.01, float(sent))))
            stream.flush()
            if not interrupted and time.monotonic() - start >= 1.0:
                recorder.send_signal(signal.SIGINT)
                interrupted = True
        stream.close()
    bag = read_bag(tmp_path / 'bag')
    assert bag.complete, bag.damage_line()
    assert [msg.point.x for _, msg in bag.decoded('/x')] == [float(index) for index in range(1, sent + 1)]
