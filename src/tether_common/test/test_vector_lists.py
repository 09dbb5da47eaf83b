"""fill_xyz: a message's list of x, y, z messages refilled from an array, its elements reused."""

from __future__ import annotations

import numpy as np
from geometry_msgs.msg import Point
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from tether_msgs.msg import TetherNodes

from tether_common.vector_lists import fill_xyz


def test_the_list_takes_the_rows_reusing_its_elements_and_growing_or_shrinking_to_them():
    msg = TetherNodes()
    fill_xyz(msg.positions, np.arange(12.0).reshape(4, 3), Point)
    first = list(msg.positions)
    fill_xyz(msg.positions, -np.arange(6.0).reshape(2, 3), Point)
    assert msg.positions[0] is first[0] and msg.positions[1] is first[1] and len(msg.positions) == 2
    fill_xyz(msg.positions, np.arange(9.0).reshape(3, 3) + 0.5, Point)
    assert msg.positions[:2] == first[:2] and len(msg.positions) == 3
    decoded = deserialize_message(serialize_message(msg), TetherNodes)
    np.testing.assert_array_equal([[p.x, p.y, p.z] for p in decoded.positions], np.arange(9.0).reshape(3, 3) + 0.5)
    fill_xyz(msg.positions, np.zeros((0, 3)), Point)
    assert msg.positions == []
