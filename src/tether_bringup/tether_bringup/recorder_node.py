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
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy
from tether_msgs.msg import LockstepAck

from tether_bringup.bag_writer import BagWriter
from tether_bringup.bag_writer import QosRecord
from tether_bringup.cdr_stamp import stamp_reader
from tether_bringup.recorder_params import PARAMETERS
from tether_common.lockstep import ACK_TOPIC
from tether_common.message_types import message_class
from tether_common.node_main import run_node
from tether_common.qos import LOCKSTEP_ACK
from tether_common.ros_parameters import declare_parameters

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
        self.bag = BagWriter(self.params['bag_directory'], flush_period=self.params['flush_period'])
        self.sim_time_ns = 0
        self._subscriptions_by_topic = {}
        self._last_change = time.monotonic()
        self._graph_signature = None
        self._ready = False
        self._expected = set(self.params['expected_nodes'])
        self._exclude = set(self.params['exclude']) | {ACK_TOPIC}
        self._ack_pub = self.create_publisher(LockstepAck, ACK_TOPIC, LOCKSTEP_ACK)
        self._ack = LockstepAck(node=self.get_fully_qualified_name())
        self._subscribe('/clock', 'rosgraph_msgs/msg/Clock', [QosRecord(depth=1)], '')
        self.create_timer(self.params['discovery_period'], self.discover)

    def discover(self) -> None:
        """Subscribe to new topics; report readiness once the graph has settled."""
        for topic, types in self.get_topic_names_and_types():
            if topic in self._subscriptions_by_topic or topic in self._exclude:
                continue
            publishers = self.get_publishers_info_by_topic(topic)
            if not publishers or len(types) != 1:
                continue
            qos = [qos_record(info.qos_profile) for info in publishers]
            self._subscribe(topic, types[0], qos, type_hash_string(publishers[0].topic_type_hash))
        self.bag.maybe_flush()
        if not self._ready and self.params['ready_file']:
            present = {name for name, _ in self.get_node_names_and_namespaces()}
            signature = (frozenset(present), frozenset(
                (topic, self.count_publishers(topic), self.count_subscribers(topic))
                for topic, _ in self.get_topic_names_and_types()))
            if signature != self._graph_signature:
                self._graph_signature = signature
                self._last_change = time.monotonic()
            settled = time.monotonic() - self._last_change >= self.params['settle_time']
            if self._expected <= present and settled and self._matched_every_publisher():
                self._ready = True
                Path(self.params['ready_file']).write_text('\n'.join(sorted(self._subscriptions_by_topic)) + '\n')
                self._acknowledge(0)

    def _matched_every_publisher(self) -> bool:
        """True once each recorded topic's subscription has matched every publisher in the graph."""
        return all(subscription.get_publisher_count() >= self.count_publishers(topic)
                   for topic, subscription in self._subscriptions_by_topic.items() if subscription is not None)

    def _subscribe(self, topic: str, type_name: str, qos: list[QosRecord], type_hash: str) -> None:
        try:
            msg_type = message_class(type_name)
        except (ImportError, AttributeError, ValueError):
            self.get_logger().warning(f'not recording {topic}: message type {type_name} is not installed')
            self._subscriptions_by_topic[topic] = None
            return
        self.bag.add_topic(topic, type_name, qos, type_hash)
        profile = qos_profile(qos, self.params['queue_depth'])
        read_stamp = stamp_reader(type_name)
        write = self.bag.write

        if topic == '/clock':
            def on_message(data: bytes) -> None:
                self.sim_time_ns = max(self.sim_time_ns, read_stamp(data))
                write(topic, data, self.sim_time_ns)
                if self._ready:
                    self._acknowledge(self.sim_time_ns)
        elif read_stamp is None:
            def on_message(data: bytes) -> None:
                write(topic, data, self.sim_time_ns)
        else:
            def on_message(data: bytes) -> None:
                stamp = read_stamp(data)
                write(topic, data, self.sim_time_ns if stamp is None else stamp)

        self._subscriptions_by_topic[topic] = self.create_subscription(
            msg_type, topic, on_message, profile, raw=True)

    def _acknowledge(self, time_ns: int) -> None:
        self._ack.done.sec, self._ack.done.nanosec = divmod(time_ns, 1_000_000_000)
        self._ack_pub.publish(self._ack)

    def destroy_node(self) -> None:
        """Finalize the bag, then destroy the node."""
        self.bag.close()
        super().destroy_node()


def main(args=None) -> None:
    """Run the recorder until shutdown; the bag is finalized on every exit path."""
    sys.exit(run_node(Recorder, args))


if __name__ == '__main__':
    main()
