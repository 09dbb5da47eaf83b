"""The single-rotation helpers against scipy's ``Rotation``, whose formulas they follow."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tether_common.rotation import matrix_to_quaternion
from tether_common.rotation import quaternion_rotation
from tether_common.rotation import rotation_vector_between

ROTATIONS = Rotation.random(200, random_state=7)


def test_matrix_to_quaternion_is_scipys_including_the_sign():
    # the random draw visits every branch: the trace and each diagonal element the largest
    choices = set()
    for rotation in ROTATIONS:
        matrix = rotation.as_matrix()
        choices.add(int(np.argmax([*np.diag(matrix), np.trace(matrix)])))
        np.testing.assert_allclose(matrix_to_quaternion(matrix), Rotation.from_matrix(matrix).as_quat(),
                                   rtol=0, atol=1e-14)
    assert choices == {0, 1, 2, 3}


def test_the_matrix_and_its_inverse_apply_as_scipys():
    vectors = np.random.default_rng(3).normal(size=(len(ROTATIONS), 3))
    for rotation, vec in zip(ROTATIONS, vectors):
        ours = quaternion_rotation(rotation.as_quat(), 'q')
        np.testing.assert_allclose(ours.apply(vec), rotation.apply(vec), rtol=0, atol=1e-14)
        np.testing.assert_allclose(ours.apply_inverse(vec), rotation.inv().apply(vec), rtol=0, atol=1e-14)


@pytest.mark.parametrize('step', [1e-6, 1e-4, 2e-3, 0.5, 3.0])
def test_rotation_vector_between_is_scipys_for_small_and_large_angles(step):
    rng = np.random.default_rng(11)
    for rotation in ROTATIONS[:50]:
        turn = Rotation.from_rotvec(step * rng.normal(size=3) / np.sqrt(3.0))
        q_from, q_to = rotation.as_quat(), (rotation * turn).as_quat()
        expected = (Rotation.from_quat(q_from).inv() * Rotation.from_quat(q_to)).as_rotvec()
        np.testing.assert_allclose(rotation_vector_between(q_from, q_to), expected, rtol=0, atol=1e-12)
        np.testing.assert_allclose(rotation_vector_between(q_from, -q_to), expected, rtol=0, atol=1e-12)


def test_a_quaternion_far_from_unit_length_is_refused_by_name():
    with pytest.raises(ValueError, match='^attitude must be a unit quaternion'):
        quaternion_rotation(np.array([0.0, 0.0, 0.0, 2.0]), 'attitude')
