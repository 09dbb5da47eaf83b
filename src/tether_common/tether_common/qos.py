"""Named QoS profiles of the tethersim graph.

Sensor streams use the sensor-data profile (best effort, shallow); commands and state use
reliable delivery with depth 10; latched status uses transient local durability.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy
from rclpy.qos import qos_profile_sensor_data

SENSOR = qos_profile_sensor_data
STATE = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE)
COMMAND = STATE
LOOP = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000, reliability=ReliabilityPolicy.RELIABLE)
"""Closed-loop streams selected by stamp (reel command, tether state): a consumer running behind
its producer must still find the message of every tick, so 10 s at 100 Hz are queued."""
LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
