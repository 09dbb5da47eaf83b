"""The time master's side of the lockstep (:mod:`tether_common.lockstep`).

Every node of a run, and the recorder, publishes on ``/lockstep/ack`` the sim time up to
which it has run all its ticks (0 once it has joined). The bringup publishes the next
``/clock`` value only once every member has acked the current one, so no node runs ahead
of the slowest, and a run's messages do not depend on how fast each process gets to run.
"""

from __future__ import annotations

from rclpy.node import Node
from tether_msgs.msg import LockstepAck

from tether_common.lockstep import ACK_TOPIC
from tether_common.lockstep import stamp_ns
from tether_common.qos import LOCKSTEP_ACK_READER


class Barrier:
    """Sim time acked by each member (fully qualified node names); -1 until it joins."""

    def __init__(self, node: Node, members: list[str]) -> None:
        self.done = {name: -1 for name in members}
        self.acks = 0
        self._subscription = node.create_subscription(LockstepAck, ACK_TOPIC, self._on_ack, LOCKSTEP_ACK_READER)

    def _on_ack(self, msg: LockstepAck) -> None:
        self.acks += 1
        previous = self.done.get(msg.node)
        if previous is not None:
            self.done[msg.node] = max(previous, stamp_ns(msg.done))

    def reached(self, time_ns: int) -> bool:
        """True once every member has acked ``time_ns`` (joined, for 0)."""
        return all(done >= time_ns for done in self.done.values())

    def behind(self, time_ns: int) -> list[str]:
        """Members that have not acked ``time_ns`` yet."""
        return sorted(name for name, done in self.done.items() if done < time_ns)
