"""Stamps read from CDR bytes equal the stamps the messages were built with."""

from __future__ import annotations

from builtin_interfaces.msg import Time
from geometry_msgs.msg import PointStamped
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float64
from visualization_msgs.msg import Marker
from visualization_msgs.msg import MarkerArray

from tether_bringup.cdr_stamp import stamp_reader

STAMP = Time(sec=12, nanosec=345_000_000)
NS = 12_345_000_000


def test_header_clock_and_first_array_element_stamps():
    point = PointStamped()
    point.header.stamp = STAMP
    point.header.frame_id = 'world'
    assert stamp_reader('geometry_msgs/msg/PointStamped')(serialize_message(point)) == NS
    assert stamp_reader('rosgraph_msgs/msg/Clock')(serialize_message(Clock(clock=STAMP))) == NS
    markers = MarkerArray(markers=[Marker(), Marker()])
    markers.markers[0].header.stamp = STAMP
    read = stamp_reader('visualization_msgs/msg/MarkerArray')
    assert read(serialize_message(markers)) == NS
    assert read(serialize_message(MarkerArray())) is None


def test_types_without_a_stamp_have_no_reader():
    assert stamp_reader('std_msgs/msg/Float64') is None
    assert serialize_message(Float64(data=1.0))
