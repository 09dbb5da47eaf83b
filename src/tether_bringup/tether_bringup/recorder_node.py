"""Record every topic of the graph, serialized, into one rosbag2-compatible MCAP.

The recorder discovers topics by polling the ROS graph, subscribes to each with the QoS
its publishers offer (best effort if any publisher is best effort, transient local if all
are) and ``raw=True``, and writes the CDR bytes untouched. Log and publish times are the
message's sim time: its stamp, read from the CDR bytes (:mod:`tether_bringup.cdr_stamp`;
``header.stamp``, the ``/clock`` value, or the first element's stamp of a message array),
and the latest ``/clock`` received for a type without one. The recorder is a member of the
lockstep (:mod:`tether_bringup.barrier`): it acks each ``/clock`` value once it has written
every message that arrived before it, so the graph cannot run ahead of the bag. Once every expected node is in the graph, the graph
(nodes, topics, and the publisher and subscription count of each topic) has not changed for
``settle_time`` and every recorded subscription has matched all the topic's publishers, it
writes ``ready_file`` so that the bringup can start the clock: nothing
published on a sim-time timer is missed.

With ``stream_fd``, the node group's recording stream (:mod:`tether_common.record_stream`),
a thread reads the CDR bytes of what the group's nodes (``stream_nodes``) publish, and a
topic whose every publisher the group has announced is recorded from there, in the order
the group published it, with no DDS subscription: the write to a reader in another process
was the largest cost of the group's thread. A topic that a process outside the group
publishes too is subscribed to as above, and its stream frames are dropped; so is a streamed
topic once such a publisher appears (then volatile: the group's publishers would resend their
history, which the bag already holds). The recorder is
ready once the group has announced its publishers; at shutdown it reads the stream to its
end (the group has exited) before it finalizes the bag.

With ``live_port``, it also serves what it writes over the Foxglove WebSocket protocol
(:mod:`tether_bringup.live_server`), announcing its URL once the graph has settled and every
topic is advertised; with ``live_wait`` it reports ready only once a client has subscribed there.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from pathlib import Path

import yaml
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy
from tether_msgs.msg import LockstepAck

from tether_bringup.bag_writer import BagWriter
from tether_bringup.bag_writer import QosRecord
from tether_bringup.cdr_stamp import stamp_reader
from tether_bringup.live_server import LiveBag
from tether_bringup.live_server import LiveServer
from tether_bringup.recorder_params import PARAMETERS
from tether_common.lockstep import ACK_TOPIC
from tether_common.message_types import message_class
from tether_common.node_main import run_node
from tether_common.qos import LOCKSTEP_ACK
from tether_common.record_stream import ANNOUNCE
from tether_common.record_stream import ANNOUNCED
from tether_common.record_stream import StreamReader
from tether_common.ros_parameters import declare_parameters

STREAM_END_TIMEOUT = 20.0
"""Seconds the recorder waits at shutdown for the end of the group's stream (the bringup stops the group first)."""
UNKNOWN_NODE = '_NODE_NAME_UNKNOWN_'
"""The node name the ROS graph gives a publisher whose node's own discovery has not arrived yet."""
_DROP = None
"""A streamed topic recorded from DDS instead (another process publishes it too): its frames are dropped."""
_RELIABILITY = {ReliabilityPolicy.RELIABLE: 'reliable', ReliabilityPolicy.BEST_EFFORT: 'best_effort'}
_DURABILITY = {DurabilityPolicy.VOLATILE: 'volatile', DurabilityPolicy.TRANSIENT_LOCAL: 'transient_local'}


def qos_record(profile) -> QosRecord:
    """Translate an offered rclpy QoS profile into rosbag2's YAML words."""
    return QosRecord(
        history='keep_last' if profile.history != HistoryPolicy.KEEP_ALL else 'keep_all',
        depth=max(profile.depth, 1) if profile.history != HistoryPolicy.KEEP_ALL else 0,
        reliability=_RELIABILITY.get(profile.reliability, 'reliable'),
        durability=_DURABILITY.get(profile.durability, 'volatile'),
    )


def qos_profile(records: list[QosRecord], depth: int) -> QoSProfile:
    """A QoS profile matching every offered one: best effort if any publisher is, transient
    local only if all are.
    """
    best_effort = any(record.reliability == 'best_effort' for record in records)
    latched = bool(records) and all(record.durability == 'transient_local' for record in records)
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def publisher_nodes(publishers) -> set[str] | None:
    """The fully qualified names of the nodes of ``publishers`` (rclpy's TopicEndpointInfo), or None while
    the graph does not know one of them yet.
    """
    if any(info.node_name == UNKNOWN_NODE for info in publishers):
        return None
    return {f'{info.node_namespace.rstrip("/")}/{info.node_name}' for info in publishers}


def streamed_topics(ready_file: Path) -> set[str]:
    """The topics a recorder's ready file says it takes from the node group's stream."""
    routes = yaml.safe_load(ready_file.read_text()) if ready_file.exists() else None
    return {topic for topic, route in routes.items() if route == 'stream'} if isinstance(routes, dict) else set()


def type_hash_string(type_hash) -> str:
    """Format an rclpy TypeHash as REP-2011 ``RIHS01_<hex>`` (empty if unknown)."""
    if type_hash is None or type_hash.version != 1:
        return ''
    return f'RIHS01_{type_hash.value.hex()}'


class Recorder(Node):
    """Subscribe to every topic and write it to a :class:`BagWriter`."""

    def __init__(self) -> None:
        super().__init__('recorder')
        self.params = declare_parameters(self, PARAMETERS)
        self.bag = BagWriter(self.params['bag_directory'], flush_period=self.params['flush_period'],
                             chunk_period=self.params['chunk_period'])
        if self.params['live_port'] >= 0:
            self.bag = LiveBag(self.bag, LiveServer(self.params['live_host'], self.params['live_port'],
                                                    self.params['live_stats_file'], self.params['live_wait']))
        self.sim_time_ns = 0
        self._subscriptions_by_topic = {}
        self._last_change = time.monotonic()
        self._graph_signature = None
        self._ready = False
        self._expected = set(self.params['expected_nodes'])
        self._exclude = set(self.params['exclude']) | {ACK_TOPIC}
        self._ack_pub = self.create_publisher(LockstepAck, ACK_TOPIC, LOCKSTEP_ACK)
        self._ack = LockstepAck(node=self.get_fully_qualified_name())
        self._lock = threading.RLock()
        self._stream_nodes = set(self.params['stream_nodes'])
        self._announced: dict[str, set[str]] = {}
        self._announcements_done = self.params['stream_fd'] < 0
        self._stream_topics: dict[int, str] = {}
        self._stream_routes: dict[str, object] = {}
        self._stream_pending: dict[str, list[bytes]] = {}
        self._streamed: dict[str, tuple[str, int]] = {}
        """Topics recorded from the stream: their type and publisher count when last checked."""
        self._closed = False
        self._stream_thread = None
        self._subscribe('/clock', 'rosgraph_msgs/msg/Clock', [QosRecord(depth=1)], '')
        if self.params['stream_fd'] >= 0:
            self._stream_thread = threading.Thread(target=self._read_stream, args=(self.params['stream_fd'],),
                                                   name='record stream', daemon=True)
            self._stream_thread.start()
        self.create_timer(self.params['discovery_period'], self.discover)

    def discover(self) -> None:
        """Subscribe to new topics (or take them from the group's stream); report readiness once the graph has settled."""
        live = self.bag.server if isinstance(self.bag, LiveBag) else None
        if live is not None and not self.params['ready_file']:
            live.announce()            # no bringup waits for this recorder: serve from the start
        waiting = False
        for topic, (type_name, count) in list(self._streamed.items()):
            if self.count_publishers(topic) != count:
                waiting |= self._check_streamed(topic, type_name)
        for topic, types in self.get_topic_names_and_types():
            if topic in self._subscriptions_by_topic or topic in self._exclude:
                continue
            publishers = self.get_publishers_info_by_topic(topic)
            if not publishers or len(types) != 1:
                continue
            qos = [qos_record(info.qos_profile) for info in publishers]
            type_hash = type_hash_string(publishers[0].topic_type_hash)
            nodes = publisher_nodes(publishers)
            if self._stream_nodes and nodes is None:
                waiting = True
                continue
            with self._lock:
                if self._stream_nodes and nodes <= self._stream_nodes:
                    if nodes <= self._announced.get(topic, set()):
                        self._record_from_stream(topic, types[0], qos, type_hash)
                        continue
                    if not self._announcements_done:
                        waiting = True
                        continue
                self._stream_routes[topic] = _DROP
                self._stream_pending.pop(topic, None)
            self._subscribe(topic, types[0], qos, type_hash)
        with self._lock:
            self.bag.maybe_flush()
        if not self._ready and self.params['ready_file'] and not waiting:
            present = {name for name, _ in self.get_node_names_and_namespaces()}
            signature = (frozenset(present), frozenset(
                (topic, self.count_publishers(topic), self.count_subscribers(topic))
                for topic, _ in self.get_topic_names_and_types()))
            if signature != self._graph_signature:
                self._graph_signature = signature
                self._last_change = time.monotonic()
            settled = time.monotonic() - self._last_change >= self.params['settle_time']
            if self._expected <= present and settled and self._matched_every_publisher():
                if live is not None:
                    live.announce()    # every channel is advertised: clients may connect now
                    if not live.ready:
                        return
                self._ready = True
                with self._lock:
                    routes = {topic: 'stream' if self._stream_routes.get(topic, _DROP) is not _DROP else 'dds'
                              for topic in sorted(self._subscriptions_by_topic)}
                Path(self.params['ready_file']).write_text(yaml.safe_dump(routes))
                self._acknowledge(0)

    def _matched_every_publisher(self) -> bool:
        """True once each recorded topic's subscription has matched every publisher in the graph."""
        return all(subscription.get_publisher_count() >= self.count_publishers(topic)
                   for topic, subscription in self._subscriptions_by_topic.items() if subscription is not None)

    def _subscribe(self, topic: str, type_name: str, qos: list[QosRecord], type_hash: str,
                   durability: DurabilityPolicy | None = None) -> None:
        msg_type = self._message_class(topic, type_name)
        if msg_type is None:
            return
        with self._lock:
            self.bag.add_topic(topic, type_name, qos, type_hash)
        profile = qos_profile(qos, self.params['queue_depth'])
        if durability is not None:
            profile.durability = durability
        self._subscriptions_by_topic[topic] = self.create_subscription(
            msg_type, topic, self._writer(topic, type_name), profile, raw=True)

    def _record_from_stream(self, topic: str, type_name: str, qos: list[QosRecord], type_hash: str) -> None:
        """Record ``topic`` from the group's stream (with the lock held): what arrived for it so far first."""
        self._subscriptions_by_topic[topic] = None
        if self._message_class(topic, type_name) is None:
            self._stream_routes[topic] = _DROP
            self._stream_pending.pop(topic, None)
            return
        self._streamed[topic] = (type_name, len(qos))
        self.bag.add_topic(topic, type_name, qos, type_hash)
        write = self._stream_routes[topic] = self._writer(topic, type_name)
        for data in self._stream_pending.pop(topic, []):
            write(data)

    def _check_streamed(self, topic: str, type_name: str) -> bool:
        """A streamed topic's publishers changed: if a node the group did not announce for it publishes it now
        (outside the group, or a publisher the group made after linking), record it from DDS from here on,
        volatile (the group's publishers would resend their history, already recorded), and drop its stream
        frames. Return True while a publisher's node is not known yet.
        """
        publishers = self.get_publishers_info_by_topic(topic)
        nodes = publisher_nodes(publishers)
        if nodes is None:
            return True
        with self._lock:
            outside = nodes - self._announced.get(topic, set())
        if not outside:
            self._streamed[topic] = (type_name, len(publishers))
            return False
        del self._streamed[topic]
        self.get_logger().warning(f'recording {topic} over DDS from now on: {", ".join(sorted(outside))} publishes '
                                  f'it too, not through the node group\'s stream')
        with self._lock:
            self._stream_routes[topic] = _DROP
        qos = [qos_record(info.qos_profile) for info in publishers]
        self._subscribe(topic, type_name, qos, type_hash_string(publishers[0].topic_type_hash),
                        durability=DurabilityPolicy.VOLATILE)
        return False

    def _message_class(self, topic: str, type_name: str):
        try:
            return message_class(type_name)
        except (ImportError, AttributeError, ValueError):
            self.get_logger().warning(f'not recording {topic}: message type {type_name} is not installed')
            self._subscriptions_by_topic[topic] = None
            return None

    def _writer(self, topic: str, type_name: str):
        """The function that writes one serialized message of ``topic`` to the bag, logged at its sim time."""
        read_stamp = stamp_reader(type_name)
        write = self.bag.write
        lock = self._lock

        if topic == '/clock':
            def on_message(data: bytes) -> None:
                with lock:
                    self.sim_time_ns = max(self.sim_time_ns, read_stamp(data))
                    write(topic, data, self.sim_time_ns)
                if self._ready:
                    self._acknowledge(self.sim_time_ns)
        elif read_stamp is None:
            def on_message(data: bytes) -> None:
                with lock:
                    write(topic, data, self.sim_time_ns)
        else:
            def on_message(data: bytes) -> None:
                stamp = read_stamp(data)
                with lock:
                    write(topic, data, self.sim_time_ns if stamp is None else stamp)
        return on_message

    def _read_stream(self, fd: int) -> None:
        """Read the group's stream to its end (the group closed it or exited)."""
        reader = StreamReader()
        try:
            while data := os.read(fd, 1 << 16):
                if not self._take(reader.feed(data)):
                    break
        except OSError as error:
            self.get_logger().error(f'reading the node group\'s recording stream (fd {fd}): {error.strerror}')
        else:
            os.close(fd)
        with self._lock:
            self._announcements_done = True
        if reader.pending:
            self.get_logger().error(f'the node group\'s recording stream ended inside a message '
                                    f'({reader.pending} bytes not recorded)')

    def _take(self, frames: list[tuple[int, int, bytes]]) -> bool:
        """Register announcements, write or hold each message; False once the bag is closed."""
        with self._lock:
            if self._closed:
                return False
            for kind, topic_id, payload in frames:
                if kind == ANNOUNCE:
                    topic, node = payload.decode().split('\n')
                    self._stream_topics[topic_id] = topic
                    self._announced.setdefault(topic, set()).add(node)
                    if topic in self._exclude:
                        self._stream_routes[topic] = _DROP
                elif kind == ANNOUNCED:
                    self._announcements_done = True
                else:
                    topic = self._stream_topics[topic_id]
                    if topic not in self._stream_routes:
                        self._stream_pending.setdefault(topic, []).append(payload)
                    elif (write := self._stream_routes[topic]) is not _DROP:
                        write(payload)
        return True

    def _acknowledge(self, time_ns: int) -> None:
        self._ack.done.sec, self._ack.done.nanosec = divmod(time_ns, 1_000_000_000)
        self._ack_pub.publish(self._ack)

    def destroy_node(self) -> None:
        """Read the group's stream to its end, finalize the bag, then destroy the node."""
        if self._stream_thread is not None:
            self._stream_thread.join(STREAM_END_TIMEOUT)
            if self._stream_thread.is_alive():
                self.get_logger().error(f'the node group\'s recording stream did not end within '
                                        f'{STREAM_END_TIMEOUT:.0f} s; finalizing the bag without the rest')
        with self._lock:
            self._closed = True
            self.bag.close()
        super().destroy_node()


def main(args=None) -> None:
    """Run the recorder until shutdown; the bag is finalized on every exit path. Ctrl-C does not
    interrupt a callback: a chunk whose write stopped halfway would leave the file unreadable.
    """
    sys.exit(run_node(Recorder, args, interrupt_callbacks=False))


if __name__ == '__main__':
    main()
