"""tether_common.cdr: the bytes rclpy's serialization gives, for every message type the graph sends."""

from __future__ import annotations

import pathlib
import random
import struct

import pytest
from geometry_msgs.msg import PointStamped
from rcl_interfaces.msg import ParameterValue
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from rosidl_parser.definition import AbstractGenericString
from rosidl_parser.definition import AbstractSequence
from rosidl_parser.definition import Array
from rosidl_parser.definition import BasicType
from rosidl_parser.definition import BoundedSequence
from rosidl_parser.definition import NamespacedType
from rosidl_parser.definition import UnboundedWString

from tether_common import cdr
from tether_common.message_types import field_class
from tether_common.message_types import message_class

MSG_DIR = pathlib.Path(__file__).resolve().parents[2] / 'tether_msgs' / 'msg'
GRAPH_TYPES = ['geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/TwistStamped', 'geometry_msgs/msg/WrenchStamped',
               'sensor_msgs/msg/Imu', 'sensor_msgs/msg/NavSatFix', 'rosgraph_msgs/msg/Clock',
               'visualization_msgs/msg/MarkerArray', 'diagnostic_msgs/msg/DiagnosticArray',
               'std_msgs/msg/Bool', 'std_msgs/msg/String'] + \
    sorted(f'tether_msgs/msg/{path.stem}' for path in MSG_DIR.glob('*.msg'))


def _value(slot_type, rng: random.Random):
    """A random value of a field: strings of 0-8 characters, sequences of 0-3 elements."""
    if isinstance(slot_type, NamespacedType):
        return _filled(field_class(slot_type)(), rng)
    if isinstance(slot_type, AbstractGenericString):
        return ''.join(rng.choice('abxyz/_') for _ in range(rng.randrange(9)))
    if isinstance(slot_type, Array):
        return [_value(slot_type.value_type, rng) for _ in range(slot_type.size)]
    if isinstance(slot_type, AbstractSequence):
        count = rng.randrange(4)
        if isinstance(slot_type, BoundedSequence):
            count = min(count, slot_type.maximum_size)
        return [_value(slot_type.value_type, rng) for _ in range(count)]
    assert isinstance(slot_type, BasicType)
    name = slot_type.typename
    if name in ('float', 'double'):
        return rng.uniform(-1e3, 1e3)
    if name == 'boolean':
        return rng.random() < 0.5
    if name == 'octet':
        return bytes([rng.randrange(256)])
    bits = int(name.removeprefix('u').removeprefix('int'))
    return rng.randrange(2**bits) if name.startswith('u') else rng.randrange(-2**(bits - 1), 2**(bits - 1))


def _filled(msg, rng: random.Random):
    for slot, slot_type in zip(msg.__slots__, msg.SLOT_TYPES):
        setattr(msg, slot.removeprefix('_'), _value(slot_type, rng))
    return msg


@pytest.mark.parametrize('type_name', GRAPH_TYPES)
def test_the_bytes_decode_to_what_rclpy_s_bytes_decode_to(type_name):
    """rclpy's CDR leaves its padding uninitialized and may end with spare bytes (it sizes the buffer
    from an estimate), so the check is: the same message decoded, and every byte that differs is
    padding, written 0 here.
    """
    cls = message_class(type_name)
    rng = random.Random(type_name)
    for index in range(100):
        msg = cls() if index == 0 else _filled(cls(), rng)
        ours, theirs = cdr.serialize(msg), serialize_message(msg)
        assert deserialize_message(ours, cls) == deserialize_message(theirs, cls)
        assert len(ours) <= len(theirs)
        assert all(a == b or a == 0 for a, b in zip(ours, theirs))
        assert cdr.serialize(msg) == ours  # padding and all: the same bytes every time


def test_a_nested_double_after_a_string_is_aligned_at_run_time():
    """The offset after a string picks one of eight packers: the Point's doubles land on multiples
    of 8 from the payload's start, whatever the frame_id's length.
    """
    for length in range(9):
        msg = PointStamped()
        msg.header.frame_id = 'w' * length
        msg.point.x, msg.point.y, msg.point.z = 1.5, -2.0, 3.25
        data = cdr.serialize(msg)
        x_offset = -(8 + 4 + length + 1) % 8 + 8 + 4 + length + 1
        assert struct.unpack_from('<3d', data, 4 + x_offset) == (1.5, -2.0, 3.25)
        assert len(data) == 4 + x_offset + 24
        assert data[4 + 8 + 4 + length + 1:4 + x_offset] == bytes(x_offset - (8 + 4 + length + 1))


def test_a_field_type_it_does_not_write_is_refused():
    """Octet sequences and wide strings are not written: the group's publishers send such messages
    as rclpy does (lockstep.GroupPublisher).
    """
    with pytest.raises(NotImplementedError, match='octet'):
        cdr.serializer(ParameterValue)

    class WideStringDouble:
        """A test double of a message class with one wide-string field."""

        __slots__ = ('_text',)
        SLOT_TYPES = (UnboundedWString(),)

    with pytest.raises(NotImplementedError, match='wide strings'):
        cdr.serializer(WideStringDouble)
