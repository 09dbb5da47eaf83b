"""Named QoS profiles of the tethersim graph.

Commands and state use reliable delivery with depth 10; latched status keeps its last
message (depth 1). Sensor streams keep the sensor-data profile's shallow history but are
reliable: in a lockstep run (:mod:`tether_common.lockstep`) a consumer waits for each
message it selects, so a dropped one would stall the run; sensor dropouts are modelled,
seeded, by the sensor nodes. Best-effort subscribers (visualization tools) still match.

Every stream a node publishes is transient local: a publisher matches a subscription only
once its own discovery has seen it, which can come after the subscription has matched the
publisher (each side discovers the other on its own). A volatile message published in that
gap is lost to the subscriber, and a lockstep consumer waiting for it stalls the run; a
transient-local publisher sends its history to the subscription when it matches it.
Volatile subscribers (visualization tools, ``/clock``) still match.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy


def _stream(depth: int) -> QoSProfile:
    """A reliable, transient-local stream keeping ``depth`` messages."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


STATE = _stream(10)
COMMAND = STATE
SENSOR = _stream(5)
LOOP = _stream(1000)
"""Closed-loop streams selected by stamp (reel command, tether state): a consumer running behind
its producer must still find the message of every tick, so 10 s at 100 Hz are queued."""
CLOCK = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE)
"""``/clock``: volatile (a late subscriber must not take old times); the time master publishes the
first value only once its publisher has matched every node's subscription."""
LATCHED = _stream(1)
LOCKSTEP_ACK = LATCHED
LOCKSTEP_ACK_READER = _stream(1000)
IDLE_READER = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.BEST_EFFORT,
                         durability=DurabilityPolicy.VOLATILE)
"""The DDS reader that keeps an in-process subscription in the graph (:func:`tether_common.lockstep.link_in_process`)
and takes nothing: best effort, so its writer sends it no heartbeats and waits for no acks; one sample kept."""
