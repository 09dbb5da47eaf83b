"""Linear 2-node string elements (Sec. 8.3, Appendix D.1-D.2), numpy form.

The compiled force kernel in :mod:`kernels` evaluates the same stencil; these functions
serve assembly, statics and diagnostics.
"""

from __future__ import annotations

import numpy as np


def n_nodes(n_elem: int) -> int:
    """Number of nodes of a string of n_elem linear elements."""
    return n_elem + 1


def element_nodes(n_elem: int) -> np.ndarray:
    """Node indices (n_elem, 2) of each element."""
    i = np.arange(n_elem)
    return np.stack([i, i + 1], axis=1)


def mass_matrix(n_elem: int, mu: float, l0: float) -> np.ndarray:
    """Consistent scalar mass matrix, Eq. 8.14 (element (mu l0 / 6) [[2, 1], [1, 2]], Eq. 8.10)."""
    n = n_nodes(n_elem)
    m = np.zeros((n, n))
    me = mu * l0 / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    for i in range(n_elem):
        m[i:i + 2, i:i + 2] += me
    return m


def gravity_weights(n_elem: int, mu: float, l0: float) -> np.ndarray:
    """Nodal share of the string weight, G_str of Eq. 8.13 (mu l0 / 2 per element end)."""
    w = np.zeros(n_nodes(n_elem))
    w[:-1] += 0.5 * mu * l0
    w[1:] += 0.5 * mu * l0
    return w


def axial_stiffness(n_elem: int, ea: float, l0: float) -> np.ndarray:
    """Scalar stiffness of axial motion of a straight taut string (tangent EA / l0 per element)."""
    n = n_nodes(n_elem)
    k = np.zeros((n, n))
    ke = ea / l0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    for i in range(n_elem):
        k[i:i + 2, i:i + 2] += ke
    return k


def strains(x: np.ndarray, l0: float) -> np.ndarray:
    """Engineering strain |r_{i+1} - r_i| / l0 - 1 of each element, shape (..., n_elem, 1)."""
    d = np.diff(x, axis=-2)
    return (np.linalg.norm(d, axis=-1) / l0 - 1.0)[..., None]


def elastic_energy(x: np.ndarray, ea: float, l0: float, tension_only: bool = True) -> np.ndarray:
    """Elastic energy (tension-only unless told otherwise) sum l0 * EA * max(eps, 0)^2 / 2 (Eq. 7.8), shape (...)."""
    eps = strains(x, l0)[..., 0]
    eps = np.maximum(eps, 0.0) if tension_only else eps
    return 0.5 * ea * l0 * np.sum(eps**2, axis=-1)


def internal_forces(x: np.ndarray, ea: float, l0: float) -> np.ndarray:
    """Nodal elastic forces q_i (r_{i+1} - r_i) with q_i from Eq. 8.8, zero in compression."""
    d = np.diff(x, axis=0)
    length = np.linalg.norm(d, axis=1)
    q = ea / l0 * np.maximum(length - l0, 0.0) / length
    f = np.zeros_like(x)
    f[:-1] += q[:, None] * d
    f[1:] -= q[:, None] * d
    return f


def hessian(x: np.ndarray, ea: float, l0: float) -> np.ndarray:
    """Hessian (3n, 3n) of the elastic energy, for static Newton solves."""
    n = x.shape[0]
    h = np.zeros((3 * n, 3 * n))
    for i in range(n - 1):
        d = x[i + 1] - x[i]
        length = np.linalg.norm(d)
        if length <= l0:
            continue
        u = d / length
        blk = ea / l0 * ((1.0 - l0 / length) * np.eye(3) + l0 / length * np.outer(u, u))
        a, b = 3 * i, 3 * i + 3
        h[a:a + 3, a:a + 3] += blk
        h[b:b + 3, b:b + 3] += blk
        h[a:a + 3, b:b + 3] -= blk
        h[b:b + 3, a:a + 3] -= blk
    return h


def interpolate(x: np.ndarray, per_element: int) -> tuple[np.ndarray, np.ndarray]:
    """Points r(zeta) (Eq. 8.5) at per_element samples per element, and their s/l0 coordinate."""
    zeta = np.arange(per_element) / per_element
    n_elem = x.shape[-2] - 1
    pts = ((1 - zeta)[:, None] * x[..., :-1, None, :] + zeta[:, None] * x[..., 1:, None, :])
    pts = pts.reshape(*x.shape[:-2], n_elem * per_element, 3)
    pts = np.concatenate([pts, x[..., -1:, :]], axis=-2)
    s = np.concatenate([(np.arange(n_elem)[:, None] + zeta).ravel(), [n_elem]])
    return pts, s


def end_tangents(x: np.ndarray, l0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """r'(s) at the first and last node (Eq. 8.7), pointing into the tether, and end strains."""
    t0 = (x[..., 1, :] - x[..., 0, :]) / l0
    t1 = (x[..., -2, :] - x[..., -1, :]) / l0
    return t0, t1, np.linalg.norm(t0, axis=-1) - 1.0, np.linalg.norm(t1, axis=-1) - 1.0
