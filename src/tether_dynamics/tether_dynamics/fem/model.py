"""Assembly of a tether scene into the arrays the compiled kernels run on (Sec. 8.3.2-8.4.4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from tether_dynamics.fem import constraints, elements_linear, elements_quadratic, kernels
from tether_dynamics.fem.effects import Drag, KelvinVoigt, Wind
from tether_dynamics.fem.end_bodies import FarEnd, Pinned, PointMass, PrescribedMotion, RigidBody, StartEnd
from tether_dynamics.fem.errors import FemError
from tether_dynamics.laws import air_block
from tether_models.constants import GRAVITY

ELEMENTS = {'linear': elements_linear, 'quadratic': elements_quadratic}
RK4_STABILITY = 2.0 * np.sqrt(2.0)
VERLET_STABILITY = 2.0


@dataclass(frozen=True)
class Tether:
    """Material and discretisation of the string (Sec. 7.2, 8.3).

    Attributes:
        length: unstretched length l, m.
        mu: linear density, kg/m.
        ea: axial stiffness EA, N.
        n_elem: number of elements N.
        element: 'linear' or 'quadratic'.
        tension_only: True (the thesis's string, Sec. 9.1.2); False makes it a spring that
            also resists compression, for diagnosing slack-taut effects.
    """

    length: float
    mu: float
    ea: float
    n_elem: int
    element: str = 'linear'
    tension_only: bool = True

    def __post_init__(self) -> None:
        if self.element not in ELEMENTS:
            msg = f"element must be 'linear' or 'quadratic', got {self.element!r}"
            raise FemError(msg)
        if self.length <= 0 or self.mu <= 0 or self.ea <= 0 or self.n_elem < 1:
            msg = 'tether needs length, mu, EA > 0 and at least one element'
            raise FemError(msg)

    @property
    def l0(self) -> float:
        """Unstretched element length l / N."""
        return self.length / self.n_elem

    @property
    def family(self):  # noqa: ANN201 - a module
        """The element module (linear or quadratic)."""
        return ELEMENTS[self.element]

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return self.family.n_nodes(self.n_elem)


@dataclass(frozen=True)
class Scene:
    """A tether between a start end (pinned or prescribed) and a far end, with effects.

    ``nodes`` holds the initial node positions (n_nodes, 3); ``velocities`` the initial node
    velocities (default zero). Effects left as None cost nothing.
    """

    tether: Tether
    start: StartEnd
    far: FarEnd
    nodes: np.ndarray
    velocities: np.ndarray | None = None
    gravity: tuple[float, float, float] = (0.0, 0.0, -GRAVITY)
    drag: Drag | None = None
    wind: Wind | None = None
    damping: KelvinVoigt | None = None
    strain_limit: float = 0.5

    def __post_init__(self) -> None:
        nodes = np.asarray(self.nodes, float)
        if nodes.shape != (self.tether.n_nodes, 3):
            msg = f'nodes must have shape ({self.tether.n_nodes}, 3), got {nodes.shape}'
            raise FemError(msg)
        if self.wind is not None and self.drag is None:
            msg = 'wind acts on the tether only through drag: give a Drag too'
            raise FemError(msg)
        if not isinstance(self.start, (Pinned, PrescribedMotion)):
            msg = 'the start end must be Pinned or PrescribedMotion'
            raise FemError(msg)


@dataclass
class Compiled:
    """A scene packed for the kernels: the model tuple, the initial state and index maps.

    The state is in generalised coordinates q: free nodes x_f = basis q + particular x_k
    (x_k the kinematic nodes); for linear elements basis = I and particular = 0, for
    quadratic ones the c1 space of :func:`constraints.c1_basis`.
    """

    scene: Scene
    mdl: tuple
    y0: np.ndarray
    free: np.ndarray
    kinematic: np.ndarray
    m_all: np.ndarray
    c_all: np.ndarray
    gravity_weights: np.ndarray
    basis: np.ndarray
    particular: np.ndarray


def _kinematic_tables(ends: list, nodes: np.ndarray, t0: float, t1: float,
                      sample_dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Sample every kinematic end on one uniform grid (pinned ends are constant)."""
    n_s = int(np.ceil((t1 - t0) / sample_dt)) + 3
    pos = np.zeros((len(ends), n_s, 3))
    vel = np.zeros_like(pos)
    acc = np.zeros_like(pos)
    for k, (end, node) in enumerate(ends):
        if isinstance(end, Pinned):
            pos[k] = np.asarray(end.position, float)
        else:
            pos[k], vel[k], acc[k] = end.tables(t0, t1, sample_dt)
        nodes[node] = pos[k, 0]
    return pos, vel, acc, n_s


def _air(drag: Drag | None, wind: Wind | None) -> np.ndarray:
    """The kernels' air block (:func:`tether_dynamics.laws.air_block`): zeros without drag."""
    if drag is None:
        return air_block(0.0, 0.0, 0.0, 0.0)
    wind = wind or Wind((0.0, 0.0, 0.0))
    return air_block(drag.air_density, drag.diameter, drag.cd_normal, drag.cd_tangential, wind.velocity, wind.alpha,
                     wind.z_ref, wind.z_ground)


def compile_scene(scene: Scene, t0: float = 0.0, t1: float = 0.0, sample_dt: float = 1e-3) -> Compiled:
    """Assemble mass (Eq. 8.14 / 8.33), constraints (Eq. 8.41) and loads for the kernels.

    ``t1`` and ``sample_dt`` set the span and grid of prescribed-motion tables; beyond t1
    the last sample is held, so pass the end of the intended run. Prescribed ends start at
    their table state; for quadratic elements the free-node initial velocities are
    corrected (least change) to satisfy the velocity-level c1 constraints.
    """
    tet = scene.tether
    fam = tet.family
    n_all = tet.n_nodes
    l0 = tet.l0
    nodes = np.array(scene.nodes, float)
    kinematic_ends: list[tuple[StartEnd | FarEnd, int]] = [(scene.start, 0)]
    far_kinematic = isinstance(scene.far, (Pinned, PrescribedMotion))
    if far_kinematic:
        kinematic_ends.append((scene.far, n_all - 1))
    kin_idx = np.array([node for _, node in kinematic_ends], np.int64)
    free = np.arange(1, n_all - 1 if far_kinematic else n_all)
    if free.size == 0:
        msg = 'the tether has no free node: use more elements'
        raise FemError(msg)
    pos, vel, acc, n_s = _kinematic_tables(kinematic_ends, nodes, t0, max(t1, t0), sample_dt)
    m_all = fam.mass_matrix(tet.n_elem, tet.mu, l0)
    c_all = constraints.c1_matrix(tet.n_elem) if tet.element == 'quadratic' else np.zeros((0, n_all))
    grav = np.asarray(scene.gravity, float)
    weights = fam.gravity_weights(tet.n_elem, tet.mu, l0)
    gload = weights[:, None] * grav[None, :]
    far = scene.far
    end_kind = 0 if far_kinematic else (1 if isinstance(far, PointMass) else 2)
    mass = getattr(far, 'mass', 0.0)
    force = np.asarray(getattr(far, 'force', (0.0, 0.0, 0.0)), float)
    if isinstance(far, RigidBody):
        pi_m = np.asarray(far.inertia, float)
        rho_c = np.asarray(far.rho_c, float)
        omega0 = np.asarray(far.omega, float)
        rot0 = np.asarray(far.rotation, float)
    else:
        pi_m, rho_c, omega0, rot0 = np.eye(3), np.zeros(3), np.zeros(3), np.eye(3)
    drag, wind, kv = scene.drag, scene.wind, scene.damping
    m_ff, m_fk = m_all[np.ix_(free, free)], m_all[np.ix_(free, kin_idx)]
    if tet.element == 'quadratic':
        z, h = constraints.c1_basis(tet.n_elem, free, kin_idx)
        z_cols, z_vals = constraints.sparse_rows(z)
        zt_cols, zt_vals = constraints.sparse_rows(z.T)
        spline, gq = np.zeros((3, tet.n_elem + 2, 3)), np.ascontiguousarray(z.T @ gload[free])
    else:
        z, h = np.eye(free.size), np.zeros((free.size, kin_idx.size))
        z_cols, z_vals = np.zeros((0, 1), np.int64), np.zeros((0, 1))
        zt_cols, zt_vals = z_cols, z_vals
        spline, gq = np.zeros((3, 0, 3)), np.zeros((0, 3))
    k_red = z.T @ m_ff @ z
    rows, cols = np.nonzero(k_red)
    k_band = constraints.banded_cholesky(k_red, int(np.max(rows - cols)))
    g_op = -np.linalg.solve(k_red, z.T @ (m_ff @ h + m_fk))
    w_last = np.linalg.solve(k_red, z[-1])
    ip = kernels.pack_ip(
        element=1 if tet.element == 'linear' else 2, n_all=n_all, n_elem=tet.n_elem, free_first=free[0],
        free_end=free[-1] + 1, end_kind=end_kind, kv_on=kv is not None, drag_on=drag is not None,
        n_kin=len(kin_idx), n_samples=n_s, tension_only=tet.tension_only,
        moving=any(isinstance(e, PrescribedMotion) for e, _ in kinematic_ends), n_q=z.shape[1])
    fp = kernels.pack_fp(
        ea=tet.ea, l0=l0, mu=tet.mu, gravity=grav, end_mass=mass, kv_c=kv.coefficient if kv else 0.0,
        air=_air(drag, wind),
        table_t0=t0, table_dt=sample_dt, end_force=force, strain_limit=scene.strain_limit,
        c_last=z[-1] @ w_last)
    x_work, v_work = np.array(nodes), np.zeros((n_all, 3))
    v_work[kin_idx] = vel[:, 0]
    mdl = kernels.pack_mdl(
        ip=ip, fp=fp, k_band=k_band, g_op=np.ascontiguousarray(g_op), gload=gload, kin_idx=kin_idx, kin_pos=pos,
        kin_vel=vel, kin_acc=acc, pi_m=pi_m, pi_inv=np.ascontiguousarray(scipy.linalg.inv(pi_m)), rho_c=rho_c,
        x=x_work, v=v_work, f=np.zeros((n_all, 3)), a_k=np.zeros((len(kin_idx), 3)), vec=np.zeros((9, 3)),
        mat=np.zeros((3, 3, 3)), z_cols=z_cols, z_vals=z_vals, zt_cols=zt_cols, zt_vals=zt_vals,
        h_op=np.ascontiguousarray(h), w_last=w_last, q=np.zeros((z.shape[1], 3)), spline=spline, gq=gq)
    v_init = np.zeros((n_all, 3)) if scene.velocities is None else np.array(scene.velocities, float)
    p0, resid_x = _coordinates(z, nodes[free] - h @ nodes[kin_idx])
    pd0, _ = _coordinates(z, v_init[free] - h @ vel[:, 0])
    y0 = np.concatenate([p0.ravel(), pd0.ravel(), omega0, rot0.ravel()])
    if resid_x > 1e-9 * max(1.0, tet.length):
        msg = f'initial nodes violate the c1 constraints (off the c1 space by {resid_x:.3g} m)'
        raise FemError(msg)
    return Compiled(scene, mdl, y0, free, kin_idx, m_all, c_all, weights, z, h)


def _coordinates(z: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares generalised coordinates q of free-node vectors: Z q closest to ``target``.

    For velocities this is the least change that satisfies the velocity-level c1 rows;
    returns q and the largest node distance left (0 when ``target`` is c1).
    """
    q = np.linalg.lstsq(z, target, rcond=None)[0]
    return q, float(np.max(np.abs(z @ q - target), initial=0.0))


def stable_step(tether: Tether, free_ends: int = 1) -> dict[str, float]:
    """Stable explicit step estimate from the highest axial mode of the taut string.

    ``omega_moordyn`` is MoorDyn's rule (2N / L) sqrt(EA / mu) for lumped masses;
    ``omega_max`` is the highest generalised eigenvalue of the consistent-mass model
    (constrained for quadratic elements, start node pinned). RK4 is stable up to
    h omega = 2 sqrt(2), velocity Verlet up to h omega = 2.
    """
    fam = tether.family
    n = tether.n_nodes
    m = fam.mass_matrix(tether.n_elem, tether.mu, tether.l0)
    k = fam.axial_stiffness(tether.n_elem, tether.ea, tether.l0)
    free = np.arange(1, n if free_ends else n - 1)
    m_f, k_f = m[np.ix_(free, free)], k[np.ix_(free, free)]
    if tether.element == 'quadratic' and tether.n_elem > 1:
        basis = scipy.linalg.null_space(constraints.c1_matrix(tether.n_elem)[:, free])
        m_f, k_f = basis.T @ m_f @ basis, basis.T @ k_f @ basis
    omega_max = float(np.sqrt(scipy.linalg.eigvalsh(k_f, m_f)[-1]))
    omega_md = 2.0 * tether.n_elem / tether.length * np.sqrt(tether.ea / tether.mu)
    return {'omega_moordyn': omega_md, 'period_moordyn': 2 * np.pi / omega_md, 'omega_max': omega_max,
            'dt_rk4': RK4_STABILITY / omega_max, 'dt_verlet': VERLET_STABILITY / omega_max}
