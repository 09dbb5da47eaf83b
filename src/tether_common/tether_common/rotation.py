"""One rotation at a time: unit quaternions (x, y, z, w, scipy's order) and rotation matrices.

scipy's ``Rotation`` computes the same for arrays of rotations, but costs 20-70 µs a call on
one (``python -m timeit``), and the nodes turn a few rotations every 10 ms tick. These
functions follow scipy's formulas, so they agree with it to rounding, signs included.
"""

from __future__ import annotations

import math

import numpy as np


class UnitQuaternion:
    """The rotation of a unit quaternion (x, y, z, w), with ``apply`` and ``as_quat`` as
    scipy's ``Rotation`` has them.
    """

    __slots__ = ('matrix', 'q')

    def __init__(self, q: np.ndarray) -> None:
        self.q = q
        x, y, z, w = q.tolist()
        self.matrix = np.array([1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w),
                                2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w),
                                2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)]).reshape(3, 3)

    def apply(self, vec: np.ndarray) -> np.ndarray:
        """The rotated vector(s)."""
        return np.asarray(vec, float) @ self.matrix.T

    def apply_inverse(self, vec: np.ndarray) -> np.ndarray:
        """The vector(s) rotated back (scipy's ``inv().apply``)."""
        return np.asarray(vec, float) @ self.matrix

    def as_quat(self) -> np.ndarray:
        """(x, y, z, w), unit length."""
        return self.q.copy()


def quaternion_rotation(q: np.ndarray, what: str) -> UnitQuaternion:
    """The rotation of an (x, y, z, w) quaternion; a one-line error if it is not near unit length."""
    q = np.asarray(q, float)
    norm = math.sqrt(q.dot(q)) if q.shape == (4,) else 0.0
    if not math.isfinite(norm) or abs(norm - 1.0) > 1e-3:
        msg = f'{what} must be a unit quaternion (x, y, z, w), got {q.tolist()}'
        raise ValueError(msg)
    return UnitQuaternion(q / norm)


def matrix_to_quaternion(matrix: np.ndarray) -> np.ndarray:
    """(x, y, z, w) of a (3, 3) rotation matrix, by the largest of the diagonal and the trace
    (scipy's ``Rotation.from_matrix(matrix).as_quat()``).
    """
    m = [[float(v) for v in row] for row in matrix]
    decision = (m[0][0], m[1][1], m[2][2], m[0][0] + m[1][1] + m[2][2])
    choice = max(range(4), key=decision.__getitem__)
    q = [0.0, 0.0, 0.0, 0.0]
    if choice == 3:
        q = [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1], 1.0 + decision[3]]
    else:
        i = choice
        j, k = (i + 1) % 3, (i + 2) % 3
        q[i] = 1.0 - decision[3] + 2.0 * m[i][i]
        q[j] = m[j][i] + m[i][j]
        q[k] = m[k][i] + m[i][k]
        q[3] = m[k][j] - m[j][k]
    norm = math.sqrt(sum(c * c for c in q))
    return np.array([c / norm for c in q])


def rotation_vector_between(q_from: np.ndarray, q_to: np.ndarray) -> np.ndarray:
    """Rotation vector (rad, in the frame of ``q_from``) of the rotation from ``q_from`` to ``q_to``,
    both (x, y, z, w): scipy's ``(Rotation.from_quat(q_from).inv() * Rotation.from_quat(q_to)).as_rotvec()``.
    """
    x1, y1, z1, w1 = (-float(q_from[0]), -float(q_from[1]), -float(q_from[2]), float(q_from[3]))
    x2, y2, z2, w2 = (float(c) for c in q_to)
    x = w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2
    y = w1 * y2 + y1 * w2 + z1 * x2 - x1 * z2
    z = w1 * z2 + z1 * w2 + x1 * y2 - y1 * x2
    w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if w < 0.0:
        norm = -norm
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    angle = 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    if angle <= 1e-3:
        angle2 = angle * angle
        scale = 2.0 + angle2 / 12.0 + 7.0 * angle2 * angle2 / 2880.0
    else:
        scale = angle / math.sin(angle / 2.0)
    return np.array([scale * x, scale * y, scale * z])
