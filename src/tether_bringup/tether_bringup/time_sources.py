"""What drives sim time in a run: a paced clock, or a recorded bag played back.

Both publish ``/clock`` from the bringup process and advance one tick per :meth:`step`;
``step`` returns False once the source is exhausted.
"""

from __future__ import annotations

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy
from rosgraph_msgs.msg import Clock

from tether_bringup.bag_reader import BagMessage
from tether_bringup.bag_writer import QosRecord
from tether_common.message_types import message_class
from tether_bringup.recorder_node import qos_profile
from tether_bringup.sim_clock import SimClock
from tether_common.lockstep import publishers_matched
from tether_common.qos import CLOCK as CLOCK_QOS


def clock_message(time_ns: int) -> Clock:
    """Build a /clock message for ``time_ns`` nanoseconds of sim time."""
    message = Clock()
    message.clock.sec, message.clock.nanosec = divmod(int(time_ns), 1_000_000_000)
    return message


class PacedClock:
    """Publish /clock every ``step`` seconds of sim time at ``rate`` times real time."""

    def __init__(self, duration: float, step: float, rate: float) -> None:
        self.duration = duration
        self.clock = SimClock(step, rate)
        self._publisher = None

    def attach(self, node: Node) -> None:
        """Create the /clock publisher on the bringup's node."""
        self._publisher = node.create_publisher(Clock, '/clock', CLOCK_QOS)

    @property
    def clock_publisher(self):
        return self._publisher

    @property
    def end_time(self) -> float:
        """Sim time at which the run ends, s."""
        return self.duration

    def contested(self, node: Node) -> dict[str, list[str]]:
        """No topic is replayed: none is contested."""
        return {}

    def matched(self, node: Node) -> bool:
        """The paced clock has no publishers but /clock (checked by the bringup)."""
        return True

    @property
    def sim_time(self) -> float:
        return self.clock.sim_time

    @property
    def published_ns(self) -> int:
        """The latest /clock value published, ns (0 before the first)."""
        return round(self.clock.sim_time * 1e9)

    def achieved_rate(self) -> float:
        return self.clock.achieved_rate()

    def step(self) -> bool:
        if self.clock.sim_time >= self.duration - 1e-12:
            return False
        sim_time = self.clock.next_tick()
        self._publisher.publish(clock_message(round(sim_time * 1e9)))
        return True


class BagPlayback:
    """Republish a bag's serialized messages with /clock taken from the bag's log times.

    Messages go out with the reliability their publishers offered when recorded, transient local
    (:mod:`tether_common.qos`: no subscription misses the first messages, whatever its durability). /clock ticks every
    ``step`` seconds of bag time and at each message's log time; a recorded /clock topic is
    not republished (the ticks replace it), as ``ros2 bag play --clock`` does.
    """

    def __init__(self, messages: list[BagMessage], topics: dict[str, tuple[str, list[QosRecord]]],
                 step: float, rate: float) -> None:
        self._messages = messages
        self._topics = topics
        self.step_ns = round(step * 1e9)
        self.start_ns = messages[0].log_time if messages else 0
        self.end_ns = messages[-1].log_time if messages else 0
        self.duration = (self.end_ns - self.start_ns) / 1e9
        self.clock = SimClock(step, rate)
        self._index = 0
        self._now_ns = self.start_ns - 1
        self._publishers = {}
        self._clock_publisher = None

    def attach(self, node: Node) -> None:
        """Create /clock and one publisher per replayed topic on the bringup's node."""
        self._clock_publisher = node.create_publisher(Clock, '/clock', CLOCK_QOS)
        for topic, (type_name, qos) in self._topics.items():
            profile = qos_profile(qos, depth=100)
            profile.durability = DurabilityPolicy.TRANSIENT_LOCAL  # matches every subscription, and none loses the first
            self._publishers[topic] = node.create_publisher(message_class(type_name), topic, profile)

    @property
    def clock_publisher(self):
        return self._clock_publisher

    @property
    def end_time(self) -> float:
        """Sim time at which the replay ends (the bag's last log time), s."""
        return self.end_ns / 1e9

    def matched(self, node: Node) -> bool:
        """True once every replay publisher has matched every subscription in the graph."""
        return publishers_matched(node, self._publishers.values())

    def contested(self, node: Node) -> dict[str, list[str]]:
        """Replayed topics that a node of the graph publishes too, with those nodes: two sources of one topic."""
        own = node.get_name()
        others = {topic: sorted({info.node_name for info in node.get_publishers_info_by_topic(topic)} - {own})
                  for topic in self._topics}
        return {topic: nodes for topic, nodes in others.items() if nodes}

    @property
    def sim_time(self) -> float:
        return max(0, self._now_ns - self.start_ns) / 1e9

    @property
    def published_ns(self) -> int:
        """The latest /clock value published, ns (0 before the first)."""
        return self._now_ns if self.clock.ticks else 0

    def achieved_rate(self) -> float:
        return self.clock.achieved_rate()

    def step(self) -> bool:
        if self._index >= len(self._messages):
            return False
        self.clock.next_tick()
        tick_end = self.start_ns + self.clock.ticks * self.step_ns
        while self._index < len(self._messages) and self._messages[self._index].log_time <= tick_end:
            message = self._messages[self._index]
            if message.log_time > self._now_ns:
                self._now_ns = message.log_time
                self._clock_publisher.publish(clock_message(self._now_ns))
            self._publishers[message.topic].publish(message.data)
            self._index += 1
        if tick_end > self._now_ns:
            self._now_ns = tick_end
            self._clock_publisher.publish(clock_message(self._now_ns))
        return True
