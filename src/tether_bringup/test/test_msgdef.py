"""Concatenated ros2msg definitions as rosbag2 writes them."""

from __future__ import annotations

import pytest
from rosbags.typesys import get_types_from_msg

from tether_bringup.errors import BagError
from tether_bringup.msgdef import SEPARATOR
from tether_bringup.msgdef import concatenated_definition
from tether_bringup.msgdef import dependencies


def test_dependencies_skip_primitives_constants_and_resolve_header_and_local_types():
    text = ('uint8 MODE_IDLE=0  # a constant\nHeader header\nfloat64[3] x\nstring<=5 s\n'
            'Point[] points\ngeometry_msgs/Vector3 v # comment\nbuiltin_interfaces/Time t\n')
    assert dependencies(text, 'geometry_msgs') == [
        'std_msgs/Header', 'geometry_msgs/Point', 'geometry_msgs/Vector3', 'builtin_interfaces/Time']


def test_custom_type_definition_is_complete_and_parses():
    text = concatenated_definition('tether_msgs/msg/TetherNodes')
    sections = text.split(SEPARATOR + '\n')
    assert sections[0].startswith('# Node positions')
    names = [section.splitlines()[0] for section in sections[1:]]
    assert names == ['MSG: std_msgs/Header', 'MSG: builtin_interfaces/Time', 'MSG: geometry_msgs/Point',
                     'MSG: geometry_msgs/Vector3']
    types = get_types_from_msg(text, 'tether_msgs/msg/TetherNodes')
    assert set(types) >= {'tether_msgs/msg/TetherNodes', 'geometry_msgs/msg/Point', 'std_msgs/msg/Header'}


def test_units_written_in_msg_travel_with_the_definition():
    text = concatenated_definition('tether_msgs/msg/ReelState')
    assert 'float64 deployed_length' in text and '# m, unstretched tether' in text


def test_unknown_type_is_a_clear_error():
    with pytest.raises(BagError, match="message package 'nope_msgs'"):
        concatenated_definition('nope_msgs/msg/Nothing')
    with pytest.raises(BagError, match='not a message type name'):
        concatenated_definition('justaname')
