"""Quadratic 3-node string elements with 2-point Gauss quadrature (Sec. 8.4, Appendix D.3-D.4).

Node 2j-1, 2j, 2j+1 of the thesis (1-based) are nodes 2j, 2j+1, 2j+2 here (0-based j).
The compiled kernels (:mod:`kernels`) evaluate the same stencil on the B-spline control
points of the c1 string (:func:`constraints.c1_basis`); the tests hold them equal.
"""

from __future__ import annotations

import numpy as np

from tether_dynamics.laws import GAUSS, quadratic_shape, quadratic_slope


def shape(zeta: np.ndarray) -> np.ndarray:
    """Shape functions S1..S3 (Eq. D.5), shape (len(zeta), 3)."""
    return np.stack(quadratic_shape(np.asarray(zeta, float)), axis=-1)


def shape_slope(zeta: np.ndarray) -> np.ndarray:
    """dS/dzeta; times 2 it gives the coefficients of l(zeta), Eq. 8.26."""
    return np.stack(quadratic_slope(np.asarray(zeta, float)), axis=-1)


def n_nodes(n_elem: int) -> int:
    """Number of nodes of a string of n_elem quadratic elements (2N + 1)."""
    return 2 * n_elem + 1


def element_nodes(n_elem: int) -> np.ndarray:
    """Node indices (n_elem, 3) of each element."""
    j = 2 * np.arange(n_elem)
    return np.stack([j, j + 1, j + 2], axis=1)


def mass_matrix(n_elem: int, mu: float, l0: float) -> np.ndarray:
    """Consistent scalar mass matrix: element (mu l0 / 30) [[4,2,-1],[2,16,2],[-1,2,4]] (Eq. D.12)."""
    n = n_nodes(n_elem)
    m = np.zeros((n, n))
    me = mu * l0 / 30.0 * np.array([[4.0, 2.0, -1.0], [2.0, 16.0, 2.0], [-1.0, 2.0, 4.0]])
    for j in range(n_elem):
        m[2 * j:2 * j + 3, 2 * j:2 * j + 3] += me
    return m


def gravity_weights(n_elem: int, mu: float, l0: float) -> np.ndarray:
    """Nodal share of the string weight, (mu l0 / 6) (1, 4, 1) per element (Eq. D.12)."""
    w = np.zeros(n_nodes(n_elem))
    for j in range(n_elem):
        w[2 * j:2 * j + 3] += mu * l0 / 6.0 * np.array([1.0, 4.0, 1.0])
    return w


def axial_stiffness(n_elem: int, ea: float, l0: float) -> np.ndarray:
    """Scalar stiffness of axial motion of a straight taut string, 2-point Gauss (Eq. D.8)."""
    n = n_nodes(n_elem)
    k = np.zeros((n, n))
    b = 2.0 * shape_slope(GAUSS)
    ke = ea / (2.0 * l0) * (b.T @ b)
    for j in range(n_elem):
        k[2 * j:2 * j + 3, 2 * j:2 * j + 3] += ke
    return k


def _lengths(x: np.ndarray) -> np.ndarray:
    """l(zeta) (Eq. 8.26 / D.11) at the Gauss points, shape (..., n_elem, 2, 3)."""
    b = 2.0 * shape_slope(GAUSS)
    n_elem = (x.shape[-2] - 1) // 2
    idx = element_nodes(n_elem)
    xe = x[..., idx, :]
    return np.einsum('gk,...ekc->...egc', b, xe)


def strains(x: np.ndarray, l0: float) -> np.ndarray:
    """Strain |l(zeta_g)| / l0 - 1 at the two Gauss points, shape (..., n_elem, 2)."""
    return np.linalg.norm(_lengths(x), axis=-1) / l0 - 1.0


def elastic_energy(x: np.ndarray, ea: float, l0: float, tension_only: bool = True) -> np.ndarray:
    """Elastic energy (tension-only unless told otherwise), 2-point Gauss: sum (l0 / 2) EA max(eps_g, 0)^2 / 2."""
    eps = strains(x, l0)
    eps = np.maximum(eps, 0.0) if tension_only else eps
    return 0.25 * ea * l0 * np.sum(eps**2, axis=(-1, -2))


def internal_forces(x: np.ndarray, ea: float, l0: float) -> np.ndarray:
    """Nodal elastic forces -sum_g q_g l(zeta_g) dS_k/dzeta (Eq. D.8-D.10), zero in compression."""
    s = shape_slope(GAUSS)
    lv = _lengths(x)
    length = np.linalg.norm(lv, axis=-1)
    q = ea / l0 * np.maximum(length - l0, 0.0) / length
    fe = -np.einsum('eg,gk,egc->ekc', q, s, lv)
    f = np.zeros_like(x)
    n_elem = (x.shape[0] - 1) // 2
    for j in range(n_elem):
        f[2 * j:2 * j + 3] += fe[j]
    return f


def hessian(x: np.ndarray, ea: float, l0: float) -> np.ndarray:
    """Hessian (3n, 3n) of the quadrature elastic energy, for static Newton solves."""
    n = x.shape[0]
    h = np.zeros((3 * n, 3 * n))
    b = 2.0 * shape_slope(GAUSS)
    lv = _lengths(x)
    for j in range(lv.shape[0]):
        for g in range(2):
            length = np.linalg.norm(lv[j, g])
            if length <= l0:
                continue
            u = lv[j, g] / length
            blk = ea / (2.0 * l0) * ((1.0 - l0 / length) * np.eye(3) + l0 / length * np.outer(u, u))
            for a in range(3):
                for c in range(3):
                    ia, ic = 3 * (2 * j + a), 3 * (2 * j + c)
                    h[ia:ia + 3, ic:ic + 3] += b[g, a] * b[g, c] * blk
    return h


def interpolate(x: np.ndarray, per_element: int) -> tuple[np.ndarray, np.ndarray]:
    """Points r(zeta) (Eq. 8.23) at per_element samples per element, and their s/l0 coordinate."""
    frac = np.arange(per_element) / per_element
    sh = shape(2.0 * frac - 1.0)
    n_elem = (x.shape[-2] - 1) // 2
    xe = x[..., element_nodes(n_elem), :]
    pts = np.einsum('zk,...ekc->...ezc', sh, xe).reshape(*x.shape[:-2], n_elem * per_element, 3)
    pts = np.concatenate([pts, x[..., -1:, :]], axis=-2)
    s = np.concatenate([(np.arange(n_elem)[:, None] + frac).ravel(), [n_elem]])
    return pts, s


def end_tangents(x: np.ndarray, l0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """r'(s) at the first and last node (Eq. 8.25 at zeta = -1, +1), pointing into the tether."""
    t0 = (-3.0 * x[..., 0, :] + 4.0 * x[..., 1, :] - x[..., 2, :]) / l0
    t1 = -(x[..., -3, :] - 4.0 * x[..., -2, :] + 3.0 * x[..., -1, :]) / l0
    return t0, t1, np.linalg.norm(t0, axis=-1) - 1.0, np.linalg.norm(t1, axis=-1) - 1.0
