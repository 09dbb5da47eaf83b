"""Compiled (numba, cache=True) right-hand side and time-stepping loops of the FEM tether.

All compiled code lives in this one module so that numba's on-disk cache is invalidated
whenever any of it changes. The model is passed as a tuple ``mdl`` built by
:mod:`tether_dynamics.fem.model`, its members in the order of :data:`MDL_FIELDS`:
ip, fp, the banded factor K_band, G, gload, the kinematic index and tables, Pi, Pi^-1,
rho_c, the work arrays X, V, F, a_k, vec (9, 3), mat (3, 3, 3), the sparse rows of Z and
Z^T, H, W_last, the generalised-force work array q (n_q, 3), spline (3, N + 2, 3), GQ.

The state is in generalised coordinates q (Eq. 8.39-8.45 solved without multipliers):
free nodes x_f = Z q + H x_k, x_k the kinematic nodes. For linear elements Z = I and
H = 0 (Z_cols empty), so q are the free nodes; for quadratic elements q are the
B-spline control points of :func:`constraints.c1_basis`, and the c1 constraints hold
exactly at every step. Z_cols / Z_vals (ZT_cols / ZT_vals) are the sparse rows of Z
(of Z^T), K_band the banded Cholesky factor of K = Z^T M_ff Z, G = -K^-1 Z^T (M_ff H + M_fk)
the map from kinematic node accelerations to qddot, W_last = K^-1 z_last (z_last the
last free node's row of Z; for the end body). Quadratic elements only: spline holds
work arrays for the control points, their velocities and forces, and GQ = Z^T G_f the
constant generalised gravity (both empty for linear elements).

Speed: the steppers unpack the tuple once and pass plain arrays down; the per-step
helpers are compiled with ``_nrt=False`` (no reference counting: they allocate nothing
and the caller owns every array). With counting on, each call's array arguments cost an
atomic increment and decrement, which was most of the run time of small models
(bench/fem_tradeoff). A helper that would allocate fails to compile, so this is checked.

The positional layout of ``ip``, ``fp`` and ``mdl`` is named once, below (``IP_*``,
``FP_*``, ``MDL_*``, in the order of ``IP_FIELDS``, ``FP_FIELDS``, ``MDL_FIELDS``); the
builder packs them by name with :func:`pack_ip`, :func:`pack_fp` and :func:`pack_mdl`,
which refuse a missing or unknown field. The constants live in this module (not a
module of their own) because numba freezes them into the cached machine code, and its
cache is keyed on this file.

State vector y = [q (3 n_q), qdot (3 n_q), Omega (3), R row-major (9)] (Eq. 8.18-8.19).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from tether_dynamics.laws import (AIR_FIELDS, GAUSS, STATUS_NONFINITE, STATUS_OK, STATUS_STRAIN, add_element_drag,
                                  kelvin_voigt, segment_strain)
from tether_dynamics.layout import check_names, offsets, pack, scalars, size

# The 2-point Gauss points of a quadratic element as its B-spline parameter u = (1 + zeta) / 2.
GAUSS_U = (0.5 + 0.5 * GAUSS[0], 0.5 + 0.5 * GAUSS[1])

IP_FIELDS = ('element', 'n_all', 'n_elem', 'free_first', 'free_end', 'end_kind', 'kv_on', 'drag_on', 'n_kin',
             'n_samples', 'tension_only', 'moving', 'n_q')
"""ip (int64): element type (1 linear, 2 quadratic), number of nodes, number of elements,
first free node, one past the last free node, end kind (0 kinematic, 1 point mass, 2 rigid
body), Kelvin-Voigt on, drag on (with the wind; its velocity is zero when there is none),
number of kinematic nodes, samples per kinematic table, tension-only, any prescribed
(moving) end, number of generalised coordinates n_q."""
(IP_ELEMENT, IP_N_ALL, IP_N_ELEM, IP_FREE_FIRST, IP_FREE_END, IP_END_KIND, IP_KV_ON, IP_DRAG_ON, IP_N_KIN,
 IP_N_SAMPLES, IP_TENSION_ONLY, IP_MOVING, IP_N_Q) = range(len(IP_FIELDS))

FP_FIELDS = (('ea', 1), ('l0', 1), ('mu', 1), ('gravity', 3), ('end_mass', 1), ('kv_c', 1), ('air', len(AIR_FIELDS)),
             ('table_t0', 1), ('table_dt', 1), ('end_force', 3), ('strain_limit', 1), ('c_last', 1))
"""fp (float64), (name, width): EA (N), element rest length l0 (m), mu (kg/m), gravity (3,
m/s^2), end mass (kg), Kelvin-Voigt coefficient (N s), the air block of drag and wind
(:data:`tether_dynamics.laws.AIR_FIELDS`), kinematic-table start time and step (s), constant
end force (3, N), strain limit, z_last . W_last (the last free node's entry of the
constrained inverse mass)."""
(FP_EA, FP_L0, FP_MU, FP_GRAVITY, FP_END_MASS, FP_KV_C, FP_AIR, FP_TABLE_T0, FP_TABLE_DT, FP_END_FORCE,
 FP_STRAIN_LIMIT, FP_C_LAST) = offsets(FP_FIELDS)
FP_SIZE = size(FP_FIELDS)

MDL_FIELDS = ('ip', 'fp', 'k_band', 'g_op', 'gload', 'kin_idx', 'kin_pos', 'kin_vel', 'kin_acc', 'pi_m', 'pi_inv',
              'rho_c', 'x', 'v', 'f', 'a_k', 'vec', 'mat', 'z_cols', 'z_vals', 'zt_cols', 'zt_vals', 'h_op',
              'w_last', 'q', 'spline', 'gq')
"""mdl (tuple), in the order the steppers unpack it; the names are the kernels' argument names."""
(MDL_IP, MDL_FP, MDL_K_BAND, MDL_G_OP, MDL_GLOAD, MDL_KIN_IDX, MDL_KIN_POS, MDL_KIN_VEL, MDL_KIN_ACC, MDL_PI_M,
 MDL_PI_INV, MDL_RHO_C, MDL_X, MDL_V, MDL_F, MDL_A_K, MDL_VEC, MDL_MAT, MDL_Z_COLS, MDL_Z_VALS, MDL_ZT_COLS,
 MDL_ZT_VALS, MDL_H_OP, MDL_W_LAST, MDL_Q, MDL_SPLINE, MDL_GQ) = range(len(MDL_FIELDS))


def pack_ip(**fields: int) -> np.ndarray:
    """The ip array from its named fields (:data:`IP_FIELDS`)."""
    return pack('ip', scalars(*IP_FIELDS), fields, np.int64)


def pack_fp(**fields: float | np.ndarray) -> np.ndarray:
    """The fp array from its named fields (:data:`FP_FIELDS`; 3-wide fields take 3-vectors)."""
    return pack('fp', FP_FIELDS, fields)


def pack_mdl(**fields: object) -> tuple:
    """The model tuple from its named members (:data:`MDL_FIELDS`)."""
    check_names('mdl', MDL_FIELDS, fields)
    return tuple(fields[n] for n in MDL_FIELDS)


@njit(cache=True, _nrt=False)
def _kinematic_nodes(t, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k):
    """Positions, velocities, accelerations of prescribed nodes at time t (Hermite tables)."""
    n_s = ip[IP_N_SAMPLES]
    h = fp[FP_TABLE_DT]
    s = (t - fp[FP_TABLE_T0]) / h
    i = int(np.floor(s))
    if i < 0:
        i = 0
    if i > n_s - 2:
        i = n_s - 2
    u = s - i
    u2 = u * u
    u3 = u2 * u
    h00 = 2.0 * u3 - 3.0 * u2 + 1.0
    h10 = u3 - 2.0 * u2 + u
    h01 = -2.0 * u3 + 3.0 * u2
    h11 = u3 - u2
    for k in range(ip[IP_N_KIN]):
        n = kin_idx[k]
        for c in range(3):
            x[n, c] = (h00 * kin_pos[k, i, c] + h10 * h * kin_vel[k, i, c]
                       + h01 * kin_pos[k, i + 1, c] + h11 * h * kin_vel[k, i + 1, c])
            v[n, c] = (h00 * kin_vel[k, i, c] + h10 * h * kin_acc[k, i, c]
                       + h01 * kin_vel[k, i + 1, c] + h11 * h * kin_acc[k, i + 1, c])
            a_k[k, c] = (1 - u) * kin_acc[k, i, c] + u * kin_acc[k, i + 1, c]


@njit(cache=True)
def _kinematic_of_model(t, mdl):
    """_kinematic_nodes on the model's tables, if an end moves."""
    if mdl[MDL_IP][IP_MOVING] == 1:
        _kinematic_nodes(t, mdl[MDL_IP], mdl[MDL_FP], mdl[MDL_KIN_IDX], mdl[MDL_KIN_POS], mdl[MDL_KIN_VEL],
                         mdl[MDL_KIN_ACC], mdl[MDL_X], mdl[MDL_V], mdl[MDL_A_K])


@njit(cache=True, _nrt=False)
def _copy_free(y, offset, ip, out):
    """Free nodes of out = q = y[offset:offset + 3 n_q] (linear elements: Z = I, H = 0)."""
    f0 = ip[IP_FREE_FIRST]
    for i in range(ip[IP_FREE_END] - f0):
        for c in range(3):
            out[f0 + i, c] = y[offset + 3 * i + c]


@njit(cache=True, _nrt=False)
def _to_nodes(y, offset, ip, z_cols, z_vals, h_op, kin_idx, out):
    """Free nodes of out = Z q + H out[kinematic], q = y[offset:offset + 3 n_q]."""
    if ip[IP_ELEMENT] == 1:
        _copy_free(y, offset, ip, out)
        return
    f0 = ip[IP_FREE_FIRST]
    nf = ip[IP_FREE_END] - f0
    for i in range(nf):
        a0 = a1 = a2 = 0.0
        for k in range(z_cols.shape[1]):
            j = offset + 3 * z_cols[i, k]
            val = z_vals[i, k]
            a0 += val * y[j]
            a1 += val * y[j + 1]
            a2 += val * y[j + 2]
        for k in range(ip[IP_N_KIN]):
            h = h_op[i, k]
            n = kin_idx[k]
            a0 += h * out[n, 0]
            a1 += h * out[n, 1]
            a2 += h * out[n, 2]
        out[f0 + i, 0], out[f0 + i, 1], out[f0 + i, 2] = a0, a1, a2


@njit(cache=True, _nrt=False)
def _unpack(y, ip, x, v, velocities, z_cols, z_vals, h_op, kin_idx):
    """Fill the free-node positions (and, if ``velocities``, velocities) from the state.

    Kinematic nodes must already hold their values (pinned: from the model; moving:
    _kinematic_nodes for the same t).
    """
    _to_nodes(y, 0, ip, z_cols, z_vals, h_op, kin_idx, x)
    if velocities:
        _to_nodes(y, 3 * ip[IP_N_Q], ip, z_cols, z_vals, h_op, kin_idx, v)


@njit(cache=True, _nrt=False)
def _linear_forces(ip, fp, x, v, f):
    """Add the linear elements' forces to F (Eq. 8.8/8.10).

    Returns the largest element length and its element: the strain check of the steppers
    comes with the forces at no extra cost.
    """
    ea, inv_l0, c_kv = fp[FP_EA], 1.0 / fp[FP_L0], fp[FP_KV_C]
    kv_on = ip[IP_KV_ON] == 1
    tension_only = ip[IP_TENSION_ONLY] == 1
    worst, where = -1.0, 0
    for e in range(ip[IP_N_ELEM]):
        d0 = x[e + 1, 0] - x[e, 0]
        d1 = x[e + 1, 1] - x[e, 1]
        d2 = x[e + 1, 2] - x[e, 2]
        w0 = w1 = w2 = 0.0
        if kv_on:
            w0, w1, w2 = v[e + 1, 0] - v[e, 0], v[e + 1, 1] - v[e, 1], v[e + 1, 2] - v[e, 2]
        length, eps, rate = segment_strain(d0, d1, d2, w0, w1, w2, inv_l0)
        if length > worst:
            worst, where = length, e
        t = kelvin_voigt(eps, rate, ea, c_kv, tension_only)[0]
        if t != 0.0:
            q = t / length
            f[e, 0] += q * d0
            f[e, 1] += q * d1
            f[e, 2] += q * d2
            f[e + 1, 0] -= q * d0
            f[e + 1, 1] -= q * d1
            f[e + 1, 2] -= q * d2
    return worst, where


@njit(cache=True, _nrt=False)
def _control_points(y, offset, ip, ends, cp):
    """All N + 2 B-spline control points of a quadratic-element string from the generalised
    coordinates y[offset:] and the kinematic end nodes ``ends`` (x or v): a kinematic end
    node is the mean of its two control points (:func:`constraints.c1_basis`).
    """
    nq = ip[IP_N_Q]
    for i in range(nq):
        for c in range(3):
            cp[1 + i, c] = y[offset + 3 * i + c]
    last = ip[IP_N_ELEM] + 1
    far = ip[IP_N_ALL] - 1
    for c in range(3):
        cp[0, c] = 2.0 * ends[0, c] - cp[1, c]
        if ip[IP_END_KIND] == 0:
            cp[last, c] = 2.0 * ends[far, c] - cp[last - 1, c]


@njit(cache=True, _nrt=False)
def _spline_forces(ip, fp, cp, cv, qf, q):
    """Add the quadratic elements' forces (Eq. D.8-D.12), as generalised forces, to q.

    Element j is the B-spline segment of control points j, j + 1, j + 2; at parameter u
    its slope l = 2 dr/dzeta = (1 - u) d_j + u d_j+1 with d_j = cp_j+1 - cp_j. The axial
    force T l / |l| at each Gauss point acts on the control points through dl/dcp: the
    same virtual work as the nodal stencil, Z^T F, without forming the nodes. Returns the
    largest l0 |r'| over Gauss points (the element length at that stretch) and its element.
    """
    ea, inv_l0, c_kv = fp[FP_EA], 1.0 / fp[FP_L0], fp[FP_KV_C]
    kv_on = ip[IP_KV_ON] == 1
    tension_only = ip[IP_TENSION_ONLY] == 1
    worst, where = -1.0, 0
    for i in range(qf.shape[0]):
        for c in range(3):
            qf[i, c] = 0.0
    for j in range(ip[IP_N_ELEM]):
        p0 = p1 = p2 = s0 = s1 = s2 = 0.0
        for g in range(2):
            u = GAUSS_U[g]
            l_0 = (1.0 - u) * (cp[j + 1, 0] - cp[j, 0]) + u * (cp[j + 2, 0] - cp[j + 1, 0])
            l_1 = (1.0 - u) * (cp[j + 1, 1] - cp[j, 1]) + u * (cp[j + 2, 1] - cp[j + 1, 1])
            l_2 = (1.0 - u) * (cp[j + 1, 2] - cp[j, 2]) + u * (cp[j + 2, 2] - cp[j + 1, 2])
            w0 = w1 = w2 = 0.0
            if kv_on:
                w0 = (1.0 - u) * (cv[j + 1, 0] - cv[j, 0]) + u * (cv[j + 2, 0] - cv[j + 1, 0])
                w1 = (1.0 - u) * (cv[j + 1, 1] - cv[j, 1]) + u * (cv[j + 2, 1] - cv[j + 1, 1])
                w2 = (1.0 - u) * (cv[j + 1, 2] - cv[j, 2]) + u * (cv[j + 2, 2] - cv[j + 1, 2])
            length, eps, rate = segment_strain(l_0, l_1, l_2, w0, w1, w2, inv_l0)
            if length > worst:
                worst, where = length, j
            t = kelvin_voigt(eps, rate, ea, c_kv, tension_only)[0]
            if t != 0.0:
                h = 0.5 * t / length
                p0 += (1.0 - u) * h * l_0
                p1 += (1.0 - u) * h * l_1
                p2 += (1.0 - u) * h * l_2
                s0 += u * h * l_0
                s1 += u * h * l_1
                s2 += u * h * l_2
        qf[j, 0] += p0
        qf[j, 1] += p1
        qf[j, 2] += p2
        qf[j + 1, 0] += s0 - p0
        qf[j + 1, 1] += s1 - p1
        qf[j + 1, 2] += s2 - p2
        qf[j + 2, 0] -= s0
        qf[j + 2, 1] -= s1
        qf[j + 2, 2] -= s2
    last = ip[IP_N_ELEM] + 1
    for i in range(ip[IP_N_Q]):
        for c in range(3):
            q[i, c] += qf[1 + i, c]
    for c in range(3):
        q[0, c] -= qf[0, c]
        if ip[IP_END_KIND] == 0:
            q[ip[IP_N_Q] - 1, c] -= qf[last, c]
    return worst, where


@njit(cache=True, _nrt=False)
def _drag_forces(ip, fp, x, v, f):
    """Add the air drag and wind on every element (:func:`tether_dynamics.laws.add_element_drag`)."""
    order = ip[IP_ELEMENT]
    for e in range(ip[IP_N_ELEM]):
        add_element_drag(x, v, e * order, order, fp[FP_L0], fp, FP_AIR, f)


@njit(cache=True, inline='always')
def _det3(a):
    """Determinant of a 3x3 matrix."""
    return (a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
            - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
            + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]))


@njit(cache=True, inline='always')
def _solve3(a, b, out, tmp):
    """Solve the 3x3 system a out = b by Cramer's rule (tmp: 3x3 scratch)."""
    det = _det3(a)
    for c in range(3):
        for r in range(3):
            for k in range(3):
                tmp[r, k] = b[r] if k == c else a[r, k]
        out[c] = _det3(tmp) / det


@njit(cache=True, inline='always')
def _cross(a, b, out):
    """out = a x b for 3-vectors."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=True, inline='always')
def _mv(a, x, out, transpose):
    """out = a x (or a^T x) for a 3x3 matrix."""
    for r in range(3):
        acc = 0.0
        for c in range(3):
            acc += (a[c, r] if transpose else a[r, c]) * x[c]
        out[r] = acc


@njit(cache=True, _nrt=False)
def _end_body(y, base, ip, fp, pi_m, pi_inv, rho_c, vec, mat):
    """Point mass or rigid body at the last free node (Eq. 7.13 condensed).

    With the body's rotational equation solved for Omega-dot and substituted, the body
    acts on its node as a force F_b - M_e a_n, M_e = m I + m^2 R rho^ Pi^-1 rho^ R^T.
    Writes F_b to vec[0], M_e to mat[0] and the torque without the a_n term to vec[8].
    """
    m = fp[FP_END_MASS]
    for c in range(3):
        vec[4, c] = fp[FP_GRAVITY + c]
        vec[0, c] = m * fp[FP_GRAVITY + c] + fp[FP_END_FORCE + c]
        vec[8, c] = 0.0
        for k in range(3):
            mat[0, c, k] = m if c == k else 0.0
    if ip[IP_END_KIND] != 2:
        return
    fb, tau, tmp, tmp2, grav = vec[0], vec[8], vec[2], vec[3], vec[4]
    me = mat[0]
    om = y[base:base + 3]
    rot = y[base + 3:base + 12].reshape((3, 3))
    _mv(pi_m, om, tmp, False)
    _cross(om, tmp, tmp2)
    _mv(rot, grav, tmp, True)
    _cross(rho_c, tmp, tau)
    for c in range(3):
        tau[c] = m * tau[c] - tmp2[c]
    _cross(om, rho_c, tmp)
    _cross(om, tmp, tmp2)
    _mv(rot, tmp2, tmp, False)
    for c in range(3):
        fb[c] -= m * tmp[c]
    _mv(pi_inv, tau, tmp, False)
    _cross(rho_c, tmp, tmp2)
    _mv(rot, tmp2, tmp, False)
    for c in range(3):
        fb[c] += m * tmp[c]
    # M_e += m^2 R S Pi^-1 S R^T with S = skew(rho_c): build column by column.
    for k in range(3):
        for c in range(3):
            tmp[c] = rot[k, c]
        _cross(rho_c, tmp, tmp2)
        _mv(pi_inv, tmp2, tmp, False)
        _cross(rho_c, tmp, tmp2)
        _mv(rot, tmp2, tmp, False)
        for r in range(3):
            me[r, k] += m * m * tmp[r]


@njit(cache=True, _nrt=False)
def _band_solve(lb, u):
    """Solve M u_new = u in place, M = L L^T with L banded: lb[i, k] = L[i, i - k] for k > 0
    and lb[i, 0] = 1 / L[i, i]. Bandwidth <= 2 (all element types here): the last two
    solved rows are carried in registers, which keeps the substitution chain short.
    """
    n, nb = lb.shape
    p0 = p1 = p2 = q0 = q1 = q2 = 0.0
    for i in range(n):
        l1 = lb[i, 1] if nb > 1 else 0.0
        l2 = lb[i, 2] if nb > 2 else 0.0
        d = lb[i, 0]
        a0 = (u[i, 0] - l1 * p0 - l2 * q0) * d
        a1 = (u[i, 1] - l1 * p1 - l2 * q1) * d
        a2 = (u[i, 2] - l1 * p2 - l2 * q2) * d
        u[i, 0], u[i, 1], u[i, 2] = a0, a1, a2
        q0, q1, q2 = p0, p1, p2
        p0, p1, p2 = a0, a1, a2
    p0 = p1 = p2 = q0 = q1 = q2 = 0.0
    for i in range(n - 1, -1, -1):
        l1 = lb[i + 1, 1] if nb > 1 and i + 1 < n else 0.0
        l2 = lb[i + 2, 2] if nb > 2 and i + 2 < n else 0.0
        d = lb[i, 0]
        a0 = (u[i, 0] - l1 * p0 - l2 * q0) * d
        a1 = (u[i, 1] - l1 * p1 - l2 * q1) * d
        a2 = (u[i, 2] - l1 * p2 - l2 * q2) * d
        u[i, 0], u[i, 1], u[i, 2] = a0, a1, a2
        q0, q1, q2 = p0, p1, p2
        p0, p1, p2 = a0, a1, a2


@njit(cache=True, _nrt=False)
def _nodal_model_forces(y, ip, fp, gload, x, v, f, q):
    """Generalised forces of linear elements (Z = I): the free nodes' gravity, elastic and
    drag forces into q. Returns :func:`_linear_forces`'s largest length and its element.
    """
    f0 = ip[IP_FREE_FIRST]
    _copy_free(y, 0, ip, x)
    if ip[IP_KV_ON] == 1 or ip[IP_DRAG_ON] == 1:
        _copy_free(y, 3 * ip[IP_N_Q], ip, v)
    for i in range(f.shape[0]):
        for c in range(3):
            f[i, c] = gload[i, c]
    worst, where = _linear_forces(ip, fp, x, v, f)
    if ip[IP_DRAG_ON] == 1:
        _drag_forces(ip, fp, x, v, f)
    for i in range(q.shape[0]):
        for c in range(3):
            q[i, c] = f[f0 + i, c]
    return worst, where


@njit(cache=True, _nrt=False)
def _spline_model_forces(y, ip, fp, kin_idx, x, v, f, z_cols, z_vals, zt_cols, zt_vals, h_op, q, spline, gq):
    """Generalised forces Z^T F_f of quadratic elements into q: the constant gravity
    Z^T G_f, the elastic forces on the control points (:func:`_spline_forces`), and drag
    (if on) through the nodes. Returns the largest stretched length and its element.
    """
    for i in range(q.shape[0]):
        for c in range(3):
            q[i, c] = gq[i, c]
    _control_points(y, 0, ip, x, spline[0])
    if ip[IP_KV_ON] == 1:
        _control_points(y, 3 * ip[IP_N_Q], ip, v, spline[1])
    worst, where = _spline_forces(ip, fp, spline[0], spline[1], spline[2], q)
    if ip[IP_DRAG_ON] == 1:
        _unpack(y, ip, x, v, True, z_cols, z_vals, h_op, kin_idx)
        f[:, :] = 0.0
        _drag_forces(ip, fp, x, v, f)
        f0 = ip[IP_FREE_FIRST]
        for j in range(q.shape[0]):
            for k in range(zt_cols.shape[1]):
                row, val = f0 + zt_cols[j, k], zt_vals[j, k]
                for c in range(3):
                    q[j, c] += val * f[row, c]
    return worst, where


@njit(cache=True, _nrt=False)
def _last_node(dy, va, ip, z_cols, z_vals, h_op, a_k, out):
    """Acceleration of the last free node from qddot = dy[va:] (and the kinematic a_k)."""
    i = ip[IP_FREE_END] - ip[IP_FREE_FIRST] - 1
    if ip[IP_ELEMENT] == 1:
        for c in range(3):
            out[c] = dy[va + 3 * i + c]
        return
    for c in range(3):
        acc = 0.0
        for k in range(z_cols.shape[1]):
            acc += z_vals[i, k] * dy[va + 3 * z_cols[i, k] + c]
        for k in range(ip[IP_N_KIN]):
            acc += h_op[i, k] * a_k[k, c]
        out[c] = acc


@njit(cache=True, _nrt=False)
def _rhs(t, y, dy, ip, fp, k_band, g_op, gload, kin_idx, kin_pos, kin_vel, kin_acc, pi_m, pi_inv, rho_c,
         x, v, f, a_k, vec, mat, z_cols, z_vals, zt_cols, zt_vals, h_op, w_last, q, spline, gq):
    """:func:`rhs` on the unpacked model tuple; returns the largest stretched length and
    its element.

    qddot = K^-1 Z^T F_f + G a_k (Eq. 8.44 in generalised coordinates, no multipliers,
    O(N) by the banded Cholesky factor of K = Z^T M_ff Z), then the end body's coupling.
    """
    nq = ip[IP_N_Q]
    if ip[IP_ELEMENT] == 1:
        worst, where = _nodal_model_forces(y, ip, fp, gload, x, v, f, q)
    else:
        worst, where = _spline_model_forces(y, ip, fp, kin_idx, x, v, f, z_cols, z_vals, zt_cols, zt_vals, h_op,
                                            q, spline, gq)
    _band_solve(k_band, q)
    va = 3 * nq
    for i in range(va):
        dy[i] = y[va + i]
    for i in range(nq):
        a0, a1, a2 = q[i, 0], q[i, 1], q[i, 2]
        for k in range(ip[IP_N_KIN]):
            gik = g_op[i, k]
            a0 += gik * a_k[k, 0]
            a1 += gik * a_k[k, 1]
            a2 += gik * a_k[k, 2]
        dy[va + 3 * i] = a0
        dy[va + 3 * i + 1] = a1
        dy[va + 3 * i + 2] = a2
    base = 6 * nq
    for i in range(12):
        dy[base + i] = 0.0
    if ip[IP_END_KIND] == 0:
        return worst, where
    _end_body(y, base, ip, fp, pi_m, pi_inv, rho_c, vec, mat)
    # vec rows: 0 F_b, 1 a_n without the body, 8 torque, 5 a_n, 6 right-hand side, 7 correction;
    # mat: 0 M_e, 1 system, 2 scratch.
    _last_node(dy, va, ip, z_cols, z_vals, h_op, a_k, vec[1])
    c_last = fp[FP_C_LAST]
    for r in range(3):
        vec[6, r] = vec[1, r] + c_last * vec[0, r]
        for c in range(3):
            mat[1, r, c] = (1.0 if r == c else 0.0) + c_last * mat[0, r, c]
    _solve3(mat[1], vec[6], vec[5], mat[2])
    for r in range(3):
        vec[7, r] = vec[0, r] - (mat[0, r, 0] * vec[5, 0] + mat[0, r, 1] * vec[5, 1] + mat[0, r, 2] * vec[5, 2])
    c0, c1, c2 = vec[7, 0], vec[7, 1], vec[7, 2]
    for i in range(nq):
        ci = w_last[i]
        dy[va + 3 * i] += ci * c0
        dy[va + 3 * i + 1] += ci * c1
        dy[va + 3 * i + 2] += ci * c2
    if ip[IP_END_KIND] == 2:
        _body_rates(y, dy, base, vec[5], fp, pi_inv, rho_c, vec)
    return worst, where


@njit(cache=True, _nrt=False)
def _body_rates(y, dy, base, a_n, fp, pi_inv, rho_c, vec):
    """Omega-dot (Eq. 7.13 rotational part, with the node acceleration a_n) and R-dot = R Omega^ (Eq. A.8)."""
    om = y[base:base + 3]
    rot = y[base + 3:base + 12].reshape((3, 3))
    tau, tmp1, tmp2 = vec[8], vec[2], vec[3]
    _mv(rot, a_n, tmp1, True)
    _cross(rho_c, tmp1, tmp2)
    for c in range(3):
        tmp2[c] = tau[c] - fp[FP_END_MASS] * tmp2[c]
    _mv(pi_inv, tmp2, tmp1, False)
    for c in range(3):
        dy[base + c] = tmp1[c]
    for r in range(3):
        for c in range(3):
            # column c of R Omega^ is R (Omega x e_c)
            k1, k2 = (c + 1) % 3, (c + 2) % 3
            dy[base + 3 + 3 * r + c] = rot[r, k1] * om[k2] - rot[r, k2] * om[k1]


@njit(cache=True)
def rhs(t, y, dy, mdl):
    """First-order ODE dy/dt (Eq. 8.18 / 8.42): nodes, end body (Eq. 7.13), rotation (Eq. A.8),
    with moving ends at time t.
    """
    _kinematic_of_model(t, mdl)
    _rhs(t, y, dy, *mdl)


@njit(cache=True)
def _renormalize(y, ip):
    """Keep the rotation block of y orthonormal: one Newton step of the polar decomposition."""
    base = 6 * ip[IP_N_Q] + 3
    rot = y[base:base + 9].reshape((3, 3)).copy()
    rot = 1.5 * rot - 0.5 * rot @ (rot.T @ rot)
    for r in range(3):
        for c in range(3):
            y[base + 3 * r + c] = rot[r, c]


@njit(cache=True, _nrt=False)
def _check(y, fp, worst, where):
    """Return (status, element, strain) for the state y, given the largest stretched length
    ``worst`` and its element from the right-hand side evaluated at y.
    """
    finite = True
    for i in range(y.size):
        finite &= np.isfinite(y[i])
    if not finite:
        return STATUS_NONFINITE, -1, np.nan
    eps = worst / fp[FP_L0] - 1.0
    if eps > fp[FP_STRAIN_LIMIT]:
        return STATUS_STRAIN, where, eps
    return STATUS_OK, where, eps


@njit(cache=True, _nrt=False)
def _check_and_record(y, t, s, rec_every, fp, worst, where, y_rec, t_rec, n_rec):
    """:func:`_check` the state y of step s at time t and, if it passed, record it every
    ``rec_every`` steps. Returns the check's (status, element, strain) and the new n_rec.
    """
    status, e, eps = _check(y, fp, worst, where)
    if status == STATUS_OK and s % rec_every == 0:
        for i in range(y.size):
            y_rec[n_rec, i] = y[i]
        t_rec[n_rec] = t
        n_rec += 1
    return status, e, eps, n_rec


@njit(cache=True)
def run_rk4(y0, t0, dt, n_steps, rec_every, mdl):
    """Classic fixed-step RK4 (the thesis's scheme, Sec. 9.1.1), checked after every step.

    The first stage of each step evaluates the forces at the state the previous step
    reached, so that is where the state is checked; one extra evaluation checks the last.
    Returns (t_rec, y_rec, n_rec, status, t_fail, element, strain).
    """
    (ip, fp, k_band, g_op, gload, kin_idx, kin_pos, kin_vel, kin_acc, pi_m, pi_inv, rho_c,
     x, v, f, a_k, vec, mat, z_cols, z_vals, zt_cols, zt_vals, h_op, w_last, q, spline, gq) = mdl
    n = y0.size
    n_rec_max = n_steps // rec_every + 1
    y_rec = np.empty((n_rec_max, n))
    t_rec = np.empty(n_rec_max)
    y = y0.copy()
    k = np.empty((4, n))
    yt = np.empty(n)
    dy = np.empty(n)
    c_stage = np.array([0.0, 0.5, 0.5, 1.0])
    moving = ip[IP_MOVING] == 1
    y_rec[0] = y
    t_rec[0] = t0
    n_rec = 1
    for s in range(n_steps + 1):
        t = t0 + s * dt
        for st in range(4 if s < n_steps else 1):
            if st == 0:
                for i in range(n):
                    yt[i] = y[i]
            else:
                h = c_stage[st] * dt
                for i in range(n):
                    yt[i] = y[i] + h * k[st - 1, i]
            if moving:
                _kinematic_nodes(t + c_stage[st] * dt, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k)
            worst, where = _rhs(t + c_stage[st] * dt, yt, dy, ip, fp, k_band, g_op, gload, kin_idx, kin_pos,
                                kin_vel, kin_acc, pi_m, pi_inv, rho_c, x, v, f, a_k, vec, mat, z_cols, z_vals,
                                zt_cols, zt_vals, h_op, w_last, q, spline, gq)
            for i in range(n):
                k[st, i] = dy[i]
            if st == 0 and s > 0:
                status, e, eps, n_rec = _check_and_record(y, t, s, rec_every, fp, worst, where, y_rec, t_rec, n_rec)
                if status != STATUS_OK:
                    return t_rec, y_rec, n_rec, status, t, e, eps
        if s == n_steps:
            break
        for i in range(n):
            y[i] += dt / 6.0 * (k[0, i] + 2.0 * k[1, i] + 2.0 * k[2, i] + k[3, i])
        if ip[IP_END_KIND] == 2:
            _renormalize(y, ip)
    return t_rec, y_rec, n_rec, STATUS_OK, t0 + n_steps * dt, -1, 0.0


@njit(cache=True)
def _rotation_step(rot, om, h):
    """R exp(h Omega^) by Rodrigues' formula (exactly orthonormal update)."""
    th = np.sqrt(om[0] ** 2 + om[1] ** 2 + om[2] ** 2) * h
    k = np.array([[0.0, -om[2], om[1]], [om[2], 0.0, -om[0]], [-om[1], om[0], 0.0]]) * h
    if th < 1e-12:
        return rot @ (np.eye(3) + k)
    return rot @ (np.eye(3) + np.sin(th) / th * k + (1.0 - np.cos(th)) / (th * th) * (k @ k))


@njit(cache=True)
def run_verlet(y0, t0, dt, n_steps, rec_every, mdl):
    """Velocity Verlet (kick-drift-kick), one force evaluation per step.

    Symplectic and time-reversible for conservative forces with pinned / point-mass ends;
    the rigid-body attitude is advanced on SO(3) by the exponential map, so R stays
    orthonormal. Velocity-dependent forces (drag, damping, gyroscopic) are evaluated with
    the half-step velocity. Returns as :func:`run_rk4`.
    """
    (ip, fp, k_band, g_op, gload, kin_idx, kin_pos, kin_vel, kin_acc, pi_m, pi_inv, rho_c,
     x, v, f, a_k, vec, mat, z_cols, z_vals, zt_cols, zt_vals, h_op, w_last, q, spline, gq) = mdl
    nq = ip[IP_N_Q]
    n = y0.size
    base = 6 * nq
    n_rec_max = n_steps // rec_every + 1
    y_rec = np.empty((n_rec_max, n))
    t_rec = np.empty(n_rec_max)
    y = y0.copy()
    dy = np.empty(n)
    y_rec[0] = y
    t_rec[0] = t0
    n_rec = 1
    moving = ip[IP_MOVING] == 1
    for s in range(n_steps + 1):
        t = t0 + s * dt
        if moving:
            _kinematic_nodes(t, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k)
        worst, where = _rhs(t, y, dy, ip, fp, k_band, g_op, gload, kin_idx, kin_pos, kin_vel, kin_acc,
                            pi_m, pi_inv, rho_c, x, v, f, a_k, vec, mat, z_cols, z_vals, zt_cols, zt_vals, h_op,
                            w_last, q, spline, gq)
        if s > 0:
            for i in range(3 * nq):
                y[3 * nq + i] += 0.5 * dt * dy[3 * nq + i]
            for i in range(3):
                y[base + i] += 0.5 * dt * dy[base + i]
            status, e, eps, n_rec = _check_and_record(y, t, s, rec_every, fp, worst, where, y_rec, t_rec, n_rec)
            if status != STATUS_OK:
                return t_rec, y_rec, n_rec, status, t, e, eps
        if s == n_steps:
            break
        for i in range(3 * nq):
            y[3 * nq + i] += 0.5 * dt * dy[3 * nq + i]
        for i in range(3):
            y[base + i] += 0.5 * dt * dy[base + i]
        for i in range(3 * nq):
            y[i] += dt * y[3 * nq + i]
        if ip[IP_END_KIND] == 2:
            rot = _rotation_step(y[base + 3:base + 12].reshape((3, 3)).copy(), y[base:base + 3], dt)
            for r in range(3):
                for c in range(3):
                    y[base + 3 + 3 * r + c] = rot[r, c]
    return t_rec, y_rec, n_rec, STATUS_OK, t0 + n_steps * dt, -1, 0.0


@njit(cache=True)
def generalized_forces(t, y, mdl):
    """Generalised forces Z^T F_f (gravity + elastic + drag) of state y, as the right-hand
    side uses them; for linear elements the free nodes' forces. For tests.
    """
    _kinematic_of_model(t, mdl)
    if mdl[MDL_IP][IP_ELEMENT] == 1:
        _nodal_model_forces(y, mdl[MDL_IP], mdl[MDL_FP], mdl[MDL_GLOAD], mdl[MDL_X], mdl[MDL_V], mdl[MDL_F],
                            mdl[MDL_Q])
    else:
        _spline_model_forces(y, mdl[MDL_IP], mdl[MDL_FP], mdl[MDL_KIN_IDX], mdl[MDL_X], mdl[MDL_V], mdl[MDL_F],
                             mdl[MDL_Z_COLS], mdl[MDL_Z_VALS], mdl[MDL_ZT_COLS], mdl[MDL_ZT_VALS], mdl[MDL_H_OP],
                             mdl[MDL_Q], mdl[MDL_SPLINE], mdl[MDL_GQ])
    return mdl[MDL_Q].copy()


@njit(cache=True)
def unpack_all(t_rec, y_rec, mdl):
    """Node positions and velocities (n, n_all, 3) of recorded states, kinematic ends filled in."""
    n_all = mdl[MDL_IP][IP_N_ALL]
    xs = np.empty((t_rec.size, n_all, 3))
    vs = np.empty((t_rec.size, n_all, 3))
    for r in range(t_rec.size):
        _kinematic_of_model(t_rec[r], mdl)
        _unpack(y_rec[r], mdl[MDL_IP], mdl[MDL_X], mdl[MDL_V], True, mdl[MDL_Z_COLS], mdl[MDL_Z_VALS],
                mdl[MDL_H_OP], mdl[MDL_KIN_IDX])
        xs[r] = mdl[MDL_X]
        vs[r] = mdl[MDL_V]
    return xs, vs
