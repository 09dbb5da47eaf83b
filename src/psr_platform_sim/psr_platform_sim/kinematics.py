"""Forward kinematics of the 3-PSR wave replicator (thesis Sec. 2.3).

Three vertical rails stand at radius ``r`` around the world z axis. Slider ``i`` moves
along rail ``i`` at height ``h_i``; an arm of length ``l`` joins it through a ball joint
to corner ``c_i`` of an equilateral platform of edge ``d``, where a hinge keeps the arm
perpendicular to the opposite platform edge. For given slider heights the nine corner
coordinates follow from nine equations (Eq. 2.1-2.3), solved here by Newton-Raphson for
many slider combinations at once (a numba kernel, parallel over the combinations).

Frame: rail 1 stands on the +y axis and the rails follow clockwise seen from above
(rail 2 at -30 deg, rail 3 at 210 deg), so that Eq. 2.4 gives an upward platform normal
and Eq. 2.5-2.6 give a right-handed body frame equal to the world frame when the sliders
are level. The platform hangs below the sliders. With Eq. 2.7-2.9 the rotation is
``R = Rx(theta) Ry(phi) Rz(psi)``: roll ``phi`` turns about the platform's axis towards
corner 1, pitch ``theta`` about the axis across it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

RAIL_ANGLES = np.radians([90.0, -30.0, 210.0])
"""Azimuth of rails 1..3 (rad), clockwise so that Eq. 2.4 points up."""

HINGE_LIMIT = 0.45
"""Lower bound of the normalized hinge product, Eq. 2.16 (hinge angle >= ~26 deg)."""


@dataclass(frozen=True)
class Design:
    """Design parameters of the mechanism (Sec. 2.3, Fig. 2.2b).

    Attributes:
        r: tower (rail) radius (m, or nondimensional with r = 1).
        l: arm length, same unit as r.
        d: platform edge length, same unit as r.
        gamma: ball-joint mounting angle (rad), measured from the rail axis towards
            the rail's radial direction (see :func:`ball_axes`).
        ball_limit: ball-joint rotation limit (rad); the prototype's joint allows 30 deg.
    """

    r: float = 1.0
    l: float = 0.975
    d: float = 1.15
    gamma: float = np.radians(30.0)
    ball_limit: float = np.radians(30.0)


PROTOTYPE = Design(r=0.40, l=0.39, d=0.46)
"""The built prototype (Sec. 2.7): Table 2.3's optimum scaled to r = 0.40 m."""


def rail_directions() -> np.ndarray:
    """Unit vectors t_i from the origin to the base of rails 1..3, shape (3, 3)."""
    return np.stack([np.cos(RAIL_ANGLES), np.sin(RAIL_ANGLES), np.zeros(3)], axis=1)


def slider_points(design: Design, heights: np.ndarray) -> np.ndarray:
    """Slider coordinates s_i for heights (..., 3), shape (..., 3, 3)."""
    heights = np.asarray(heights, dtype=float)
    s = np.broadcast_to(design.r * rail_directions(), heights.shape + (3,)).copy()
    s[..., 2] = heights
    return s


def initial_guess(design: Design, heights: np.ndarray) -> np.ndarray:
    """Corners of a level platform hanging below each slider, a Newton start (..., 3, 3)."""
    heights = np.asarray(heights, dtype=float)
    radius = design.d / np.sqrt(3.0)
    gap = design.r - radius
    drop = np.sqrt(max(design.l**2 - gap**2, 0.01 * design.l**2))
    c = np.broadcast_to(radius * rail_directions(), heights.shape + (3,)).copy()
    c[..., 2] = heights - drop
    return c


@numba.njit(cache=True)
def _residual_jacobian(s, c, l, d, f, jac):
    """Eq. 2.1-2.3 for one configuration: residual f (9) and Jacobian jac (9, 9)."""
    jac[:, :] = 0.0
    for i in range(3):
        j = (i + 1) % 3
        k = (i + 2) % 3
        arm0 = s[i, 0] - c[i, 0]
        arm1 = s[i, 1] - c[i, 1]
        arm2 = s[i, 2] - c[i, 2]
        # Eq. 2.1, squared: |s_i - c_i|^2 - l^2 = 0
        f[i] = arm0 * arm0 + arm1 * arm1 + arm2 * arm2 - l * l
        jac[i, 3 * i] = -2.0 * arm0
        jac[i, 3 * i + 1] = -2.0 * arm1
        jac[i, 3 * i + 2] = -2.0 * arm2
        # Eq. 2.2, squared: |c_i - c_j|^2 - d^2 = 0
        e0 = c[i, 0] - c[j, 0]
        e1 = c[i, 1] - c[j, 1]
        e2 = c[i, 2] - c[j, 2]
        f[3 + i] = e0 * e0 + e1 * e1 + e2 * e2 - d * d
        jac[3 + i, 3 * i] = 2.0 * e0
        jac[3 + i, 3 * i + 1] = 2.0 * e1
        jac[3 + i, 3 * i + 2] = 2.0 * e2
        jac[3 + i, 3 * j] = -2.0 * e0
        jac[3 + i, 3 * j + 1] = -2.0 * e1
        jac[3 + i, 3 * j + 2] = -2.0 * e2
        # Eq. 2.3: <s_i - c_i, c_j - c_k> = 0
        b0 = c[j, 0] - c[k, 0]
        b1 = c[j, 1] - c[k, 1]
        b2 = c[j, 2] - c[k, 2]
        f[6 + i] = arm0 * b0 + arm1 * b1 + arm2 * b2
        jac[6 + i, 3 * i] = -b0
        jac[6 + i, 3 * i + 1] = -b1
        jac[6 + i, 3 * i + 2] = -b2
        jac[6 + i, 3 * j] += arm0
        jac[6 + i, 3 * j + 1] += arm1
        jac[6 + i, 3 * j + 2] += arm2
        jac[6 + i, 3 * k] -= arm0
        jac[6 + i, 3 * k + 1] -= arm1
        jac[6 + i, 3 * k + 2] -= arm2


@numba.njit(cache=True)
def _solve_linear(a, b):
    """Solve a x = b in place (Gaussian elimination, partial pivoting); False if singular."""
    n = b.shape[0]
    for col in range(n):
        pivot = col
        for row in range(col + 1, n):
            if abs(a[row, col]) > abs(a[pivot, col]):
                pivot = row
        if abs(a[pivot, col]) < 1e-14:
            return False
        if pivot != col:
            for m in range(n):
                a[col, m], a[pivot, m] = a[pivot, m], a[col, m]
            b[col], b[pivot] = b[pivot], b[col]
        for row in range(col + 1, n):
            factor = a[row, col] / a[col, col]
            for m in range(col, n):
                a[row, m] -= factor * a[col, m]
            b[row] -= factor * b[col]
    for col in range(n - 1, -1, -1):
        total = b[col]
        for m in range(col + 1, n):
            total -= a[col, m] * b[m]
        b[col] = total / a[col, col]
    return True


@numba.njit(parallel=True, cache=True)
def _newton_batch(sliders, guess, l, d, tol, max_iter, corners, residual, converged):
    n = sliders.shape[0]
    for q in numba.prange(n):
        f = np.empty(9)
        jac = np.empty((9, 9))
        c = guess[q].copy()
        s = sliders[q]
        ok = False
        for _ in range(max_iter):
            _residual_jacobian(s, c, l, d, f, jac)
            worst = 0.0
            for m in range(9):
                worst = max(worst, abs(f[m]))
            if worst <= tol:
                ok = True
                break
            if worst > 1e6 or not np.isfinite(worst):
                break
            for m in range(9):
                f[m] = -f[m]
            if not _solve_linear(jac, f):
                break
            for m in range(9):
                c[m // 3, m % 3] += f[m]
        _residual_jacobian(s, c, l, d, f, jac)
        worst = 0.0
        for m in range(9):
            worst = max(worst, abs(f[m]))
        corners[q] = c
        residual[q] = worst
        converged[q] = ok or worst <= tol


def solve_corners(design: Design, heights: np.ndarray, guess: np.ndarray | None = None,
                  tol: float = 1e-13, max_iter: int = 20) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Solve Eq. 2.1-2.3 for the platform corners by Newton-Raphson.

    Args:
        design: mechanism parameters.
        heights: slider heights, shape (..., 3).
        guess: starting corners (..., 3, 3); a level hanging platform by default.
        tol: bound on the largest residual of the squared equations (length^2, scaled
            by r^2).
        max_iter: Newton iteration limit; from the level-platform guess every solution of
            the thesis's study grid converges within 12 iterations (a limit of 40 finds
            the same set), so the limit mostly bounds the work on unreachable heights.

    Returns:
        corners (..., 3, 3), the largest residual (...,) and a converged flag (...,).
    """
    heights = np.asarray(heights, dtype=float)
    shape = heights.shape[:-1]
    sliders = slider_points(design, heights).reshape(-1, 3, 3)
    start = initial_guess(design, heights) if guess is None else np.asarray(guess, dtype=float)
    start = np.ascontiguousarray(np.broadcast_to(start, shape + (3, 3)).reshape(-1, 3, 3))
    n = sliders.shape[0]
    corners = np.empty((n, 3, 3))
    residual = np.empty(n)
    converged = np.empty(n, dtype=np.bool_)
    _newton_batch(np.ascontiguousarray(sliders), start, design.l, design.d,
                  tol * design.r**2, max_iter, corners, residual, converged)
    return corners.reshape(shape + (3, 3)), residual.reshape(shape), converged.reshape(shape)


def constraint_residuals(design: Design, heights: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Residuals of Eq. 2.1-2.3 in their printed (unsquared) form, shape (..., 9)."""
    s = slider_points(design, heights)
    arm = s - corners
    edges = corners - np.roll(corners, -1, axis=-2)
    back = np.roll(corners, -1, axis=-2) - np.roll(corners, -2, axis=-2)
    eq1 = np.linalg.norm(arm, axis=-1) - design.l  # Eq. 2.1
    eq2 = np.linalg.norm(edges, axis=-1) - design.d  # Eq. 2.2
    eq3 = np.einsum('...k,...k->...', arm, back)  # Eq. 2.3
    return np.concatenate([eq1, eq2, eq3], axis=-1)


@dataclass(frozen=True)
class Pose:
    """Platform pose from its corners (Eq. 2.4-2.9); arrays share the batch shape.

    Attributes:
        p: platform centre (..., 3), the corners' mean.
        rotation: body axes [x', y', z'] as columns (..., 3, 3).
        roll, pitch, yaw: Eq. 2.7, 2.8, 2.9 (rad).
    """

    p: np.ndarray
    rotation: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray


def platform_pose(corners: np.ndarray) -> Pose:
    """Centre, body frame and roll, pitch, yaw of the platform (Eq. 2.4-2.9)."""
    c1, c2, c3 = corners[..., 0, :], corners[..., 1, :], corners[..., 2, :]
    p = corners.mean(axis=-2)
    z = np.cross(c1 - c3, c1 - c2)  # Eq. 2.4
    z /= np.linalg.norm(z, axis=-1, keepdims=True)
    y = (c1 - p) / np.linalg.norm(c1 - p, axis=-1, keepdims=True)  # Eq. 2.5
    x = np.cross(y, z)  # Eq. 2.6
    roll = np.arcsin(np.clip(z[..., 0], -1.0, 1.0))  # Eq. 2.7
    cos_roll = np.cos(roll)
    pitch = -np.arcsin(np.clip(z[..., 1] / cos_roll, -1.0, 1.0))  # Eq. 2.8
    yaw = -np.arcsin(np.clip(y[..., 0] / cos_roll, -1.0, 1.0))  # Eq. 2.9
    return Pose(p, np.stack([x, y, z], axis=-1), roll, pitch, yaw)


def rotation_from_angles(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """The 1-2-3 rotation Rx(pitch) Ry(roll) Rz(yaw) that Eq. 2.7-2.9 invert, (..., 3, 3)."""
    def axis_rotation(angle, a, b):
        angle = np.asarray(angle, dtype=float)
        m = np.zeros(angle.shape + (3, 3))
        m[..., a, a] = np.cos(angle)
        m[..., b, b] = np.cos(angle)
        m[..., a, b] = -np.sin(angle)
        m[..., b, a] = np.sin(angle)
        m[..., 3 - a - b, 3 - a - b] = 1.0
        return m

    rx = axis_rotation(pitch, 1, 2)
    ry = axis_rotation(roll, 2, 0)
    rz = axis_rotation(yaw, 0, 1)
    return rx @ ry @ rz


def hinge_angles(design: Design, heights: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Hinge angles delta_i (rad), Eq. 2.10, shape (..., 3)."""
    p = corners.mean(axis=-2, keepdims=True)
    arm = slider_points(design, heights) - corners
    radial = corners - p
    cosine = np.einsum('...k,...k->...', radial, arm) / (np.linalg.norm(radial, axis=-1) * design.l)
    return np.arccos(np.clip(cosine, -1.0, 1.0))


def ball_axes(gamma: float) -> np.ndarray:
    """Ball-joint mounting axes b_i (Eq. 2.12-2.13), shape (3, 3).

    Eq. 2.12 rotates the rail's radial unit vector t_i by gamma; read literally (gamma up
    from the horizontal) the neutral arm of Table 2.3's optimum would sit 40 deg off the
    axis, beyond the 30 deg joint. The optimal gamma of Table 2.3 instead tracks the
    neutral arm's angle from the vertical plus ~10 deg, so here the axis is tilted by
    gamma from the rail (vertical) towards t_i: b_i = cos(gamma) z + sin(gamma) t_i.
    """
    b = np.sin(gamma) * rail_directions()
    b[:, 2] = np.cos(gamma)
    return b


def ball_angles(design: Design, heights: np.ndarray, corners: np.ndarray,
                gamma: float | None = None) -> np.ndarray:
    """Ball-joint angles beta_i (rad), Eq. 2.11, shape (..., 3)."""
    gamma = design.gamma if gamma is None else gamma
    arm = slider_points(design, heights) - corners
    cosine = np.einsum('...ik,ik->...i', arm, ball_axes(gamma)) / design.l
    return np.arccos(np.clip(cosine, -1.0, 1.0))


def physical_margins(design: Design, heights: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest over the arms of Eq. 2.14 <s_i - c_i, t_i> and of Eq. 2.16's normalized <s_i - c_i, z'>/l."""
    arm = slider_points(design, heights) - corners
    tower = np.einsum('...ik,ik->...i', arm, rail_directions())  # Eq. 2.14
    normal = platform_pose(corners).rotation[..., :, 2]
    hinge = np.einsum('...ik,...k->...i', arm, normal) / design.l  # Eq. 2.15 / 2.16
    return tower.min(axis=-1), hinge.min(axis=-1)


def feasible(design: Design, heights: np.ndarray, corners: np.ndarray, converged: np.ndarray,
             hinge_limit: float = 0.0) -> np.ndarray:
    """True where a solution exists and satisfies Eq. 2.14 and Eq. 2.15 (2.16 with hinge_limit = 0.45)."""
    tower, hinge = physical_margins(design, heights, corners)
    return converged & (tower >= 0.0) & (hinge >= hinge_limit)


def forward(design: Design, heights: np.ndarray, guess: np.ndarray | None = None) -> tuple[Pose, np.ndarray, np.ndarray]:
    """Pose for slider heights: solve Eq. 2.1-2.3 and apply Eq. 2.4-2.9.

    Returns the pose, the corners and a flag that is True where the solution converged
    and satisfies the physical constraints Eq. 2.14-2.15.
    """
    corners, _, converged = solve_corners(design, heights, guess)
    return platform_pose(corners), corners, feasible(design, heights, corners, converged)
