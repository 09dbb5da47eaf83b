"""Per-record diagnostics of a run: energies, constraint residuals, strains, end tension and angle."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tether_dynamics.fem.end_bodies import PointMass, RigidBody
from tether_dynamics.fem.integrators import Trajectory
from tether_dynamics.fem.model import Compiled


@dataclass
class Diagnostics:
    """Diagnostics at each recorded time.

    Energies in J (Eq. 7.2, 7.6, 7.8, 7.9): kinetic (string + end body), gravity (relative
    to z = 0), elastic (tension-only, same quadrature as the forces), total. Constraint
    residuals (m, m/s) are the largest |C r| and |C rdot| of the c1 rows (Eq. 8.41, zero for
    linear elements). strains: (n, n_elem, n_points). Tensions (N) and elevation angles (deg,
    of the tether tangent above horizontal, pointing into the tether) at the start and far
    end. length: stretched length of the tether (m). rotation_error: max |R^T R - I|.
    """

    t: np.ndarray
    kinetic: np.ndarray
    gravity: np.ndarray
    elastic: np.ndarray
    total: np.ndarray
    constraint_position: np.ndarray
    constraint_velocity: np.ndarray
    strains: np.ndarray
    tension_start: np.ndarray
    tension_end: np.ndarray
    angle_start: np.ndarray
    angle_end: np.ndarray
    length: np.ndarray
    rotation_error: np.ndarray


def compute(model: Compiled, traj: Trajectory) -> Diagnostics:
    """Evaluate the diagnostics for every recorded state of ``traj``."""
    scene = model.scene
    tet = scene.tether
    fam = tet.family
    grav = np.asarray(scene.gravity, float)
    x, v = traj.nodes, traj.velocities
    kinetic = 0.5 * np.einsum('ric,ij,rjc->r', v, model.m_all, v)
    gravity = -np.einsum('i,ric,c->r', model.gravity_weights, x, grav)
    far = scene.far
    if isinstance(far, (PointMass, RigidBody)):
        m = far.mass
        kinetic += 0.5 * m * np.sum(v[:, -1] ** 2, axis=1)
        com = x[:, -1].copy()
        if isinstance(far, RigidBody):
            rho = np.asarray(far.rho_c, float)
            pi_m = np.asarray(far.inertia, float)
            rot_rho = np.einsum('rij,rj->ri', traj.rotation, np.cross(traj.omega, rho[None, :]))
            kinetic += m * np.sum(v[:, -1] * rot_rho, axis=1)
            kinetic += 0.5 * np.einsum('ri,ij,rj->r', traj.omega, pi_m, traj.omega)
            com += np.einsum('rij,j->ri', traj.rotation, rho)
        gravity -= m * com @ grav
    elastic = fam.elastic_energy(x, tet.ea, tet.l0, tet.tension_only)
    if model.c_all.shape[0]:
        cpos = np.max(np.abs(np.einsum('ki,ric->rkc', model.c_all, x)), axis=(1, 2))
        cvel = np.max(np.abs(np.einsum('ki,ric->rkc', model.c_all, v)), axis=(1, 2))
    else:
        cpos = cvel = np.zeros(len(traj.t))
    strains = fam.strains(x, tet.l0)
    t0, t1, e0, e1 = fam.end_tangents(x, tet.l0)

    def angle(tv: np.ndarray) -> np.ndarray:
        return np.degrees(np.arctan2(tv[:, 2], np.hypot(tv[:, 0], tv[:, 1])))
    pts, _ = fam.interpolate(x, 16)
    length = np.sum(np.linalg.norm(np.diff(pts, axis=1), axis=2), axis=1)
    rot_err = np.max(np.abs(np.einsum('rki,rkj->rij', traj.rotation, traj.rotation) - np.eye(3)), axis=(1, 2))
    return Diagnostics(traj.t, kinetic, gravity, elastic, kinetic + gravity + elastic, cpos, cvel, strains,
                       tet.ea * np.maximum(e0, 0.0), tet.ea * np.maximum(e1, 0.0), angle(t0), angle(t1),
                       length, rot_err)
