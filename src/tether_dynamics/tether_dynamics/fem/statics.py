"""Static hanging shape of the discrete tether with both ends held (initial conditions, Sec. 9.1.1).

The potential energy (tension-only elastic + gravity) is convex in the node positions, so
a damped Newton iteration on it converges to the unique equilibrium; for quadratic
elements it runs in the null space of the c1 constraints (Eq. 8.41).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from tether_dynamics.fem import constraints
from tether_dynamics.fem.errors import FemError
from tether_dynamics.fem.model import Tether
from tether_models.constants import GRAVITY


def _initial_guess(tether: Tether, start: np.ndarray, end: np.ndarray, gdir: np.ndarray) -> np.ndarray:
    """A parabola through both ends, in the plane of the chord and gravity, about as long as the tether."""
    n = tether.n_nodes
    s = np.linspace(0.0, 1.0, n)
    chord = end - start
    span = float(np.linalg.norm(chord))
    extra = max(tether.length * 1.002 - span, 1e-3 * tether.length)
    sag = np.sqrt(3.0 * span * extra / 8.0)
    down = gdir - chord * (gdir @ chord) / (span**2)
    if np.linalg.norm(down) < 1e-9:
        down = np.cross(chord, [1.0, 0.0, 0.0])
        if np.linalg.norm(down) < 1e-9:
            down = np.cross(chord, [0.0, 1.0, 0.0])
    down /= np.linalg.norm(down)
    return start + s[:, None] * chord + (4.0 * sag * s * (1.0 - s))[:, None] * down


def hanging_shape(tether: Tether, start: np.ndarray, end: np.ndarray,
                  gravity: tuple[float, float, float] = (0.0, 0.0, -GRAVITY),
                  tol: float = 1e-11, max_iter: int = 200) -> np.ndarray:
    """Node positions (n_nodes, 3) of the static equilibrium with both end nodes held.

    Converged when the largest residual force is below tol * EA. Raises FemError if Newton
    does not converge in max_iter iterations.
    """
    fam = tether.family
    start, end = np.asarray(start, float), np.asarray(end, float)
    grav = np.asarray(gravity, float)
    gnorm = np.linalg.norm(grav)
    gdir = grav / gnorm if gnorm > 0 else np.array([0.0, 0.0, -1.0])
    n = tether.n_nodes
    x = _initial_guess(tether, start, end, gdir)
    weights = fam.gravity_weights(tether.n_elem, tether.mu, tether.l0)
    free = np.arange(1, n - 1)
    if tether.element == 'quadratic' and tether.n_elem > 1:
        basis = scipy.linalg.null_space(constraints.c1_matrix(tether.n_elem)[:, free])
        x = constraints.project_c1(x, tether.n_elem)
    else:
        basis = None
    big = None if basis is None else np.kron(basis, np.eye(3))
    idx = (3 * free[:, None] + np.arange(3)).ravel()

    def energy(xx: np.ndarray) -> float:
        return float(fam.elastic_energy(xx, tether.ea, tether.l0) - np.sum(weights[:, None] * grav * xx))

    for _ in range(max_iter):
        f = fam.internal_forces(x, tether.ea, tether.l0) + weights[:, None] * grav
        grad = -f[free].ravel() if big is None else -big.T @ f[free].ravel()
        if np.max(np.abs(grad)) < tol * tether.ea:
            return x
        hess = fam.hessian(x, tether.ea, tether.l0)
        h_r = hess[np.ix_(idx, idx)] if big is None else big.T @ hess[np.ix_(idx, idx)] @ big
        h_r += 1e-9 * tether.ea / tether.l0 * np.eye(h_r.shape[0])
        step = -np.linalg.solve(h_r, grad)
        e0 = energy(x)
        alpha = 1.0
        while alpha > 1e-12:
            trial = x.copy()
            trial[free] += (alpha * step if big is None else big @ (alpha * step)).reshape(-1, 3)
            if energy(trial) <= e0 + 1e-4 * alpha * grad @ step + 1e-13 * (abs(e0) + 1.0):
                break
            alpha *= 0.5
        x = trial
    msg = (f'static hanging shape did not converge (residual force {np.max(np.abs(grad)):.3g} N); '
           'are the ends farther apart than the tether can stretch?')
    raise FemError(msg)
