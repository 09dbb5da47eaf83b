"""geometry_fill: fields set as Python floats, equal to a float() of each element; lists of x, y, z messages
refilled from an array, their elements reused.
"""

from __future__ import annotations

import math

import numpy as np
from geometry_msgs.msg import Point
from geometry_msgs.msg import Quaternion
from geometry_msgs.msg import Vector3
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from tether_msgs.msg import TetherNodes

from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.geometry_fill import fill_xyz


def test_a_vector_gets_floats_equal_to_each_element():
    values = np.array([0.1, -2.5e-12, np.float64(3.0) / 7.0])
    for target in (Vector3(), Point()):
        fill_vector(target, values)
        assert [target.x, target.y, target.z] == [float(v) for v in values]
        assert all(type(v) is float for v in (target.x, target.y, target.z))


def test_a_sequence_of_ints_and_a_nan_pass_as_floats():
    target = Vector3()
    fill_vector(target, [1, 2, math.nan])
    assert (target.x, target.y) == (1.0, 2.0) and type(target.x) is float and math.isnan(target.z)


def test_a_quaternion_gets_x_y_z_w_in_order():
    target = Quaternion()
    fill_quaternion(target, np.array([0.5, -0.5, 0.25, 0.625], dtype=np.float32))
    assert (target.x, target.y, target.z, target.w) == (0.5, -0.5, 0.25, 0.625)
    assert type(target.w) is float


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
