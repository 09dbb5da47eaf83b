"""Named QoS profiles of the tethersim graph.

Commands and state use reliable delivery with depth 10; latched status uses transient
local durability. Sensor streams keep the sensor-data profile's shallow history but are
reliable: in a lockstep run (:mod:`tether_common.lockstep`) a consumer waits for each
message it selects, so a dropped one would stall the run; sensor dropouts are modelled,
seeded, by the sensor nodes. Best-effort subscribers (visualization tools) still match.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy

STATE = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE)
COMMAND = STATE
SENSOR = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=5, reliability=ReliabilityPolicy.RELIABLE)
LOOP = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000, reliability=ReliabilityPolicy.RELIABLE)
"""Closed-loop streams selected by stamp (reel command, tether state): a consumer running behind
its producer must still find the message of every tick, so 10 s at 100 Hz are queued."""
CLOCK = STATE
LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
LATCHED_STATE = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=STATE.depth,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""A latched state (``/uav/state``) that is also a lockstep input: the last state for a late joiner,
and a history, as :data:`STATE`'s, for a reader running behind."""
LOCKSTEP_ACK = LATCHED
LOCKSTEP_ACK_READER = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1000,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
