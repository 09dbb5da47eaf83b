"""c1 continuity of quadratic elements (Eq. 8.39-8.45): the constraint rows, and a banded
basis of the constrained space with which the kernels solve the multiplier system of
Eq. 8.44 in O(N), in generalised coordinates that satisfy the constraints exactly.
"""

from __future__ import annotations

import numpy as np


def c1_matrix(n_elem: int) -> np.ndarray:
    """Scalar constraint rows (n_elem - 1, 2N + 1): r_{2j-1} - 4 r_2j + 6 r_{2j+1} - 4 r_{2j+2} + r_{2j+3} = 0.

    Equal slope r'(zeta = 1) of element k and r'(zeta = -1) of element k + 1 (Eq. 8.41),
    applied per coordinate; on velocities and accelerations it is the same row.
    """
    c = np.zeros((max(n_elem - 1, 0), 2 * n_elem + 1))
    for j in range(n_elem - 1):
        c[j, 2 * j:2 * j + 5] = [1.0, -4.0, 6.0, -4.0, 1.0]
    return c


def project_c1(nodes: np.ndarray, n_elem: int) -> np.ndarray:
    """Smallest change of the inner nodes that makes a quadratic-element string c1 (Eq. 8.41).

    The two end nodes stay where they are; useful to start from an analytic shape.
    """
    x = np.array(nodes, float)
    c = c1_matrix(n_elem)
    if c.shape[0] == 0:
        return x
    inner = np.arange(1, x.shape[0] - 1)
    c_f = c[:, inner]
    resid = c @ x
    x[inner] -= c_f.T @ np.linalg.solve(c_f @ c_f.T, resid)
    return x


def banded_cholesky(m: np.ndarray, bandwidth: int) -> np.ndarray:
    """Lower Cholesky factor of a banded SPD matrix in band storage.

    out[i, k] = L[i, i - k] for k >= 1 and out[i, 0] = 1 / L[i, i] (the kernels multiply).
    The kernels' banded solve handles bandwidths up to 2.
    """
    if bandwidth > 2:
        msg = f'banded solve supports bandwidth <= 2, got {bandwidth}'
        raise ValueError(msg)
    low = np.linalg.cholesky(m)
    n = m.shape[0]
    out = np.zeros((n, bandwidth + 1))
    for k in range(1, bandwidth + 1):
        out[k:, k] = np.diagonal(low, -k)
    out[:, 0] = 1.0 / np.diagonal(low)
    return out


def _bspline_nodes(n_elem: int) -> np.ndarray:
    """Node positions (2N + 1) of a uniform quadratic B-spline with N + 2 control points.

    End node (q_k + q_k+1) / 2, midpoint (q_k + 6 q_k+1 + q_k+2) / 8: every such string is
    c1 (Eq. 8.41), and every c1 string is one.
    """
    n = n_elem
    b = np.zeros((2 * n + 1, n + 2))
    for k in range(n):
        b[2 * k, k:k + 2] = 0.5
        b[2 * k + 1, k:k + 3] = [0.125, 0.75, 0.125]
    b[2 * n, n:n + 2] = 0.5
    return b


def c1_basis(n_elem: int, free: np.ndarray, kinematic: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Generalised coordinates of a c1 quadratic-element string: x_f = Z q + H x_k.

    Z (free nodes x control points) is a banded basis of the free-node vectors satisfying
    the c1 rows (Eq. 8.41) with the kinematic nodes at zero: C_f Z = 0, full column rank
    nf - (N - 1). H (free nodes x kinematic nodes) is a particular solution,
    C_f H = -C_k. Both come from the B-spline form of the string: a kinematic end node
    x_k = (q_0 + q_1) / 2 ties its outer control point, q_0 = 2 x_k - q_1. Each node
    depends on at most 3 control points, so Z^T M_ff Z is banded (bandwidth 2).
    """
    n = n_elem
    b = _bspline_nodes(n)
    far_kinematic = 2 * n in set(kinematic.tolist())
    keep = list(range(1, n + 1)) + ([] if far_kinematic else [n + 1])
    t = np.zeros((n + 2, len(keep)))
    t[keep, np.arange(len(keep))] = 1.0
    t[0] = -t[1]
    tied = {0: 0, 2 * n: n + 1}
    h = np.column_stack([2.0 * b[free, tied[int(k)]] for k in kinematic])
    if far_kinematic:
        t[n + 1] = -t[n]
    return b[free] @ t, h


def sparse_rows(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows of a sparse matrix as (columns, values), padded with column 0 and value 0."""
    width = max(int(np.max(np.count_nonzero(z, axis=1))), 1)
    cols = np.zeros((z.shape[0], width), np.int64)
    vals = np.zeros((z.shape[0], width))
    for i in range(z.shape[0]):
        nz = np.nonzero(z[i])[0]
        cols[i, :nz.size] = nz
        vals[i, :nz.size] = z[i, nz]
    return cols, vals
