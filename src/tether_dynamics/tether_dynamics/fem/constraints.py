"""c1 continuity of quadratic elements by Lagrange multipliers (Eq. 8.39-8.45), and the
constrained solve operators for the free nodes.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.linalg.lapack


def c1_matrix(n_elem: int) -> np.ndarray:
    """Scalar constraint rows (n_elem - 1, 2N + 1): r_{2j-1} - 4 r_2j + 6 r_{2j+1} - 4 r_{2j+2} + r_{2j+3} = 0.

    Equal slope r'(zeta = 1) of element k and r'(zeta = -1) of element k + 1 (Eq. 8.41),
    applied per coordinate; on velocities and accelerations it is the same row.
    """
    c = np.zeros((max(n_elem - 1, 0), 2 * n_elem + 1))
    for j in range(n_elem - 1):
        c[j, 2 * j:2 * j + 5] = [1.0, -4.0, 6.0, -4.0, 1.0]
    return c


def constrained_operators(m_ff: np.ndarray, m_fk: np.ndarray, c_f: np.ndarray,
                          c_k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve the multiplier system of Eq. 8.44 once, as operators on forces.

    The system  [M_ff C_f^T; C_f 0] [a_f; lambda] = [F_f - M_fk a_k; -C_k a_k]  has the
    solution a_f = P F_f + G a_k. Returns (P, G); with no constraints P = M_ff^-1.
    """
    m_inv = scipy.linalg.inv(m_ff)
    if c_f.shape[0] == 0:
        return m_inv, -m_inv @ m_fk
    mc = m_inv @ c_f.T
    s_inv = scipy.linalg.inv(c_f @ mc)
    p = m_inv - mc @ s_inv @ mc.T
    w = mc @ s_inv
    return p, -p @ m_fk - w @ c_k


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
    """
    low = np.linalg.cholesky(m)
    n = m.shape[0]
    out = np.zeros((n, bandwidth + 1))
    for k in range(1, bandwidth + 1):
        out[k:, k] = np.diagonal(low, -k)
    out[:, 0] = 1.0 / np.diagonal(low)
    return out


def banded_kkt(m_ff: np.ndarray, c_f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """Banded LU of the multiplier system [M_ff C_f^T; C_f 0] of Eq. 8.44 (factorised once).

    Each multiplier is placed right after the middle of the nodes its c1 row couples, so
    the matrix stays banded (a few sub- and superdiagonals for any N) and one solve costs
    O(N) instead of the O(N^2) of a dense Schur complement. LAPACK gbtrf with partial
    pivoting (the diagonal of the multiplier block is zero).

    Returns (lu, piv, row, kl, ku): lu[j] = column j of gbtrf's band storage, piv the
    0-based row swaps, row[i] the row of free node i in the interleaved ordering.
    """
    nf, nc = m_ff.shape[0], c_f.shape[0]
    key = np.concatenate([np.arange(nf, dtype=float),
                          [np.mean(np.nonzero(c_f[j])[0]) + 0.5 for j in range(nc)]])
    order = np.argsort(key, kind='stable')
    kkt = np.block([[m_ff, c_f.T], [c_f, np.zeros((nc, nc))]])[np.ix_(order, order)]
    rows, cols = np.nonzero(kkt)
    kl, ku = int(np.max(rows - cols)), int(np.max(cols - rows))
    n = nf + nc
    ab = np.zeros((2 * kl + ku + 1, n))
    for i, j in zip(rows, cols):
        ab[kl + ku + i - j, j] = kkt[i, j]
    lu, piv, info = scipy.linalg.lapack.dgbtrf(ab, kl, ku)
    if info != 0:
        msg = f'c1 multiplier system is singular (gbtrf info {info})'
        raise ValueError(msg)
    row = np.empty(nf, np.int64)
    row[order[order < nf]] = np.nonzero(order < nf)[0]
    return np.ascontiguousarray(lu.T), piv.astype(np.int64), row, kl, ku
