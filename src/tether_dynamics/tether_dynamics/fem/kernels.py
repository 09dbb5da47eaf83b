"""Compiled (numba, cache=True) right-hand side and time-stepping loops of the FEM tether.

All compiled code lives in this one module so that numba's on-disk cache is invalidated
whenever any of it changes. The model is passed as a tuple ``mdl`` built by
:mod:`tether_dynamics.fem.model`:

    (ip, fp, L_band, G, gload, kin_idx, kin_pos, kin_vel, kin_acc, Pi, Pi_inv, rho_c,
     X, V, F, A_kin, vec_scratch (9, 3), mat_scratch (3, 3, 3),
     c1_cols, c1_vals, S_inv, P_last, work (n_f, 3), work (n_c, 3), work (n_f, 3))

L_band is the banded Cholesky factor of the free-node mass matrix, c1_cols / c1_vals the
sparse c1 rows on free nodes, S_inv the inverse constraint Schur complement, P_last the
last column of the constrained inverse mass (for the end body), G the map from kinematic
node accelerations to free node accelerations.

ip (int64): element type (1 linear, 2 quadratic), n_all nodes, n_elem, first free node f0,
one past the last free node f1, end kind (0 kinematic, 1 point mass, 2 rigid body),
Kelvin-Voigt on, drag on, wind on, number of kinematic nodes, samples per kinematic table,
tension-only, any prescribed (moving) end.
fp (float64): EA, l0, mu, g (3), end mass, Kelvin-Voigt c, air density, Cd normal,
Cd tangential, diameter, wind U (3), wind z_ref, wind alpha, wind z_ground, table t0,
table dt, end force (3), strain limit.

State vector y = [r_f (3 n_f), rdot_f (3 n_f), Omega (3), R row-major (9)] (Eq. 8.18-8.19).
"""

from __future__ import annotations

import numpy as np
from numba import njit

SQRT3_INV = 1.0 / np.sqrt(3.0)
STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_STRAIN = 2


@njit(cache=True)
def _kinematic_nodes(t, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k):
    """Positions, velocities, accelerations of prescribed nodes at time t (Hermite tables).

    Not inlined on purpose: it runs only with a moving end, and inlining it costs every
    right-hand side reference-count work even when the branch is not taken.
    """
    n_s = ip[10]
    h = fp[19]
    s = (t - fp[18]) / h
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
    for k in range(ip[9]):
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
    if mdl[0][12] == 1:
        _kinematic_nodes(t, mdl[0], mdl[1], mdl[5], mdl[6], mdl[7], mdl[8], mdl[12], mdl[13], mdl[15])


@njit(cache=True, inline='always')
def _unpack(y, mdl):
    """Fill the free-node position / velocity work arrays from the state.

    Moving (prescribed) ends are set separately by _kinematic_nodes for the same t.
    """
    ip = mdl[0]
    x, v = mdl[12], mdl[13]
    f0, f1 = ip[3], ip[4]
    nf = f1 - f0
    for i in range(nf):
        for c in range(3):
            x[f0 + i, c] = y[3 * i + c]
            v[f0 + i, c] = y[3 * nf + 3 * i + c]



@njit(cache=True, inline='always')
def _wind(z, fp):
    """Wind velocity at height z (uniform if alpha = 0, else power-law shear)."""
    if fp[16] == 0.0:
        return fp[12], fp[13], fp[14]
    dz = z - fp[17]
    if dz <= 0.0:
        return 0.0, 0.0, 0.0
    s = (dz / fp[15]) ** fp[16]
    return fp[12] * s, fp[13] * s, fp[14] * s


@njit(cache=True, inline='always')
def _tension(length, l_dot_l, ea, l0, kv_on, c_kv, tension_only):
    """Axial force at one point: EA eps (+ c deps/dt), zero if eps <= 0 (tension-only, Sec. 9.1.2)."""
    eps = length * (1.0 / l0) - 1.0
    if eps <= 0.0 and tension_only:
        return 0.0
    t = ea * eps
    if kv_on:
        t += c_kv * l_dot_l / (length * l0)
        if t < 0.0 and tension_only:
            t = 0.0
    return t


@njit(cache=True, inline='always')
def _elastic_forces(mdl):
    """Add element forces to F: Eq. 8.8/8.10 (linear) or Eq. D.8-D.12 (quadratic)."""
    ip, fp = mdl[0], mdl[1]
    x, v, f = mdl[12], mdl[13], mdl[14]
    ea, l0, c_kv = fp[0], fp[1], fp[7]
    kv_on = ip[6] == 1
    tension_only = ip[11] == 1
    if ip[0] == 1:
        for e in range(ip[2]):
            d0 = x[e + 1, 0] - x[e, 0]
            d1 = x[e + 1, 1] - x[e, 1]
            d2 = x[e + 1, 2] - x[e, 2]
            length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            ldl = 0.0
            if kv_on:
                ldl = (d0 * (v[e + 1, 0] - v[e, 0]) + d1 * (v[e + 1, 1] - v[e, 1])
                       + d2 * (v[e + 1, 2] - v[e, 2]))
            t = _tension(length, ldl, ea, l0, kv_on, c_kv, tension_only)
            if t != 0.0:
                q = t / length
                f[e, 0] += q * d0
                f[e, 1] += q * d1
                f[e, 2] += q * d2
                f[e + 1, 0] -= q * d0
                f[e + 1, 1] -= q * d1
                f[e + 1, 2] -= q * d2
    else:
        for j in range(ip[2]):
            n0 = 2 * j
            for g in range(2):
                z = -SQRT3_INV if g == 0 else SQRT3_INV
                s0, s1, s2 = z - 0.5, -2.0 * z, z + 0.5
                l_0 = 2.0 * (s0 * x[n0, 0] + s1 * x[n0 + 1, 0] + s2 * x[n0 + 2, 0])
                l_1 = 2.0 * (s0 * x[n0, 1] + s1 * x[n0 + 1, 1] + s2 * x[n0 + 2, 1])
                l_2 = 2.0 * (s0 * x[n0, 2] + s1 * x[n0 + 1, 2] + s2 * x[n0 + 2, 2])
                length = np.sqrt(l_0 * l_0 + l_1 * l_1 + l_2 * l_2)
                ldl = 0.0
                if kv_on:
                    w0 = 2.0 * (s0 * v[n0, 0] + s1 * v[n0 + 1, 0] + s2 * v[n0 + 2, 0])
                    w1 = 2.0 * (s0 * v[n0, 1] + s1 * v[n0 + 1, 1] + s2 * v[n0 + 2, 1])
                    w2 = 2.0 * (s0 * v[n0, 2] + s1 * v[n0 + 1, 2] + s2 * v[n0 + 2, 2])
                    ldl = l_0 * w0 + l_1 * w1 + l_2 * w2
                t = _tension(length, ldl, ea, l0, kv_on, c_kv, tension_only)
                if t != 0.0:
                    q = t / length
                    for k in range(3):
                        sk = s0 if k == 0 else (s1 if k == 1 else s2)
                        f[n0 + k, 0] -= q * l_0 * sk
                        f[n0 + k, 1] -= q * l_1 * sk
                        f[n0 + k, 2] -= q * l_2 * sk


@njit(cache=True)
def _drag_forces(ip, fp, x, v, f):
    """Add air drag 1/2 rho |u| u C_D A (normal and tangential) at 2 Gauss points per element."""
    l0 = fp[1]
    half_rho_d = 0.5 * fp[8] * fp[11]
    cdn, cdt = fp[9], np.pi * fp[10]
    npe = 2 if ip[0] == 1 else 3
    sh = np.zeros(3)
    sl = np.zeros(3)
    for e in range(ip[2]):
        n0 = e * (npe - 1)
        for g in range(2):
            if npe == 2:
                z = 0.5 - 0.5 * SQRT3_INV if g == 0 else 0.5 + 0.5 * SQRT3_INV
                sh[0], sh[1] = 1.0 - z, z
                sl[0], sl[1] = -1.0 / l0, 1.0 / l0
                wjac = 0.5 * l0
            else:
                z = -SQRT3_INV if g == 0 else SQRT3_INV
                sh[0], sh[1], sh[2] = (z * z - z) / 2, 1 - z * z, (z * z + z) / 2
                sl[0], sl[1], sl[2] = (2 * z - 1) / l0, -4 * z / l0, (2 * z + 1) / l0
                wjac = 0.5 * l0
            r0 = r1 = r2 = 0.0
            u0 = u1 = u2 = 0.0
            t0 = t1 = t2 = 0.0
            for k in range(npe):
                r0 += sh[k] * x[n0 + k, 0]
                r1 += sh[k] * x[n0 + k, 1]
                r2 += sh[k] * x[n0 + k, 2]
                u0 -= sh[k] * v[n0 + k, 0]
                u1 -= sh[k] * v[n0 + k, 1]
                u2 -= sh[k] * v[n0 + k, 2]
                t0 += sl[k] * x[n0 + k, 0]
                t1 += sl[k] * x[n0 + k, 1]
                t2 += sl[k] * x[n0 + k, 2]
            if ip[8] == 1:
                w0, w1, w2 = _wind(r2, fp)
                u0 += w0
                u1 += w1
                u2 += w2
            stretch = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
            if stretch == 0.0:
                continue
            e0, e1, e2 = t0 / stretch, t1 / stretch, t2 / stretch
            ut = u0 * e0 + u1 * e1 + u2 * e2
            un0, un1, un2 = u0 - ut * e0, u1 - ut * e1, u2 - ut * e2
            unm = np.sqrt(un0 * un0 + un1 * un1 + un2 * un2)
            k_n = half_rho_d * stretch * cdn * unm
            k_t = half_rho_d * stretch * cdt * abs(ut)
            fx = k_n * un0 + k_t * ut * e0
            fy = k_n * un1 + k_t * ut * e1
            fz = k_n * un2 + k_t * ut * e2
            for k in range(npe):
                wk = wjac * sh[k]
                f[n0 + k, 0] += wk * fx
                f[n0 + k, 1] += wk * fy
                f[n0 + k, 2] += wk * fz


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


@njit(cache=True, inline='always')
def _end_body(y, base, mdl):
    """Point mass or rigid body at the last free node (Eq. 7.13 condensed).

    With the body's rotational equation solved for Omega-dot and substituted, the body
    acts on its node as a force F_b - M_e a_n, M_e = m I + m^2 R rho^ Pi^-1 rho^ R^T.
    Writes F_b to vec[0], M_e to mat[0] and the torque without the a_n term to vec[8].
    """
    ip, fp = mdl[0], mdl[1]
    pi_m, pi_inv, rho_c = mdl[9], mdl[10], mdl[11]
    vec, mat = mdl[16], mdl[17]
    m = fp[6]
    fb, tau, tmp, tmp2, grav = vec[0], vec[8], vec[2], vec[3], vec[4]
    me = mat[0]
    for c in range(3):
        grav[c] = fp[3 + c]
        fb[c] = m * grav[c] + fp[20 + c]
        tau[c] = 0.0
        for k in range(3):
            me[c, k] = m if c == k else 0.0
    if ip[5] != 2:
        return
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


@njit(cache=True, inline='always')
def _band_solve(lb, u):
    """Solve M u_new = u in place, M = L L^T with L banded: lb[i, k] = L[i, i - k] for k > 0
    and lb[i, 0] = 1 / L[i, i]."""
    n, nb = lb.shape
    for i in range(n):
        a0, a1, a2 = u[i, 0], u[i, 1], u[i, 2]
        for k in range(1, min(nb, i + 1)):
            lik = lb[i, k]
            a0 -= lik * u[i - k, 0]
            a1 -= lik * u[i - k, 1]
            a2 -= lik * u[i - k, 2]
        d = lb[i, 0]
        u[i, 0], u[i, 1], u[i, 2] = a0 * d, a1 * d, a2 * d
    for i in range(n - 1, -1, -1):
        a0, a1, a2 = u[i, 0], u[i, 1], u[i, 2]
        for k in range(1, min(nb, n - i)):
            lik = lb[i + k, k]
            a0 -= lik * u[i + k, 0]
            a1 -= lik * u[i + k, 1]
            a2 -= lik * u[i + k, 2]
        d = lb[i, 0]
        u[i, 0], u[i, 1], u[i, 2] = a0 * d, a1 * d, a2 * d


@njit(cache=True, inline='always')
def _constrained_solve(mdl):
    """u = P F_f: the multiplier system of Eq. 8.44 solved through M = L L^T (banded) and
    the constraint Schur complement S = C M^-1 C^T (precomputed inverse):
    u = M^-1 F - M^-1 C^T S^-1 C M^-1 F.
    """
    ip, f, lb = mdl[0], mdl[14], mdl[2]
    cf_cols, cf_vals, s_inv = mdl[18], mdl[19], mdl[20]
    u, w, z = mdl[22], mdl[23], mdl[24]
    f0 = ip[3]
    nf = ip[4] - f0
    nc = cf_cols.shape[0]
    for i in range(nf):
        for c in range(3):
            u[i, c] = f[f0 + i, c]
    _band_solve(lb, u)
    if nc > 0:
        for j in range(nc):
            for c in range(3):
                acc = 0.0
                for k in range(cf_cols.shape[1]):
                    col = cf_cols[j, k]
                    if col >= 0:
                        acc += cf_vals[j, k] * u[col, c]
                w[j, c] = acc
        z[:, :] = 0.0
        for j in range(nc):
            l0 = l1 = l2 = 0.0
            for i in range(nc):
                sji = s_inv[j, i]
                l0 += sji * w[i, 0]
                l1 += sji * w[i, 1]
                l2 += sji * w[i, 2]
            for k in range(cf_cols.shape[1]):
                col = cf_cols[j, k]
                if col >= 0:
                    v = cf_vals[j, k]
                    z[col, 0] += v * l0
                    z[col, 1] += v * l1
                    z[col, 2] += v * l2
        _band_solve(lb, z)
        for i in range(nf):
            for c in range(3):
                u[i, c] -= z[i, c]


@njit(cache=True, inline='always')
def rhs(t, y, dy, mdl):
    """First-order ODE dy/dt (Eq. 8.18 / 8.42): nodes, end body (Eq. 7.13), rotation (Eq. A.8).

    Moving ends must already be set to time t (_kinematic_nodes); the steppers do that.
    """
    ip, fp, g_op, gload = mdl[0], mdl[1], mdl[3], mdl[4]
    pi_inv, rho_c, p_last = mdl[10], mdl[11], mdl[21]
    f, a_k, vec, mat = mdl[14], mdl[15], mdl[16], mdl[17]
    f0, f1 = ip[3], ip[4]
    nf = f1 - f0
    _unpack(y, mdl)
    f[:, :] = gload
    _elastic_forces(mdl)
    if ip[7] == 1:
        _drag_forces(ip, fp, mdl[12], mdl[13], f)
    for i in range(3 * nf):
        dy[i] = y[3 * nf + i]
    va = 3 * nf
    u = mdl[22]
    _constrained_solve(mdl)
    for i in range(nf):
        a0, a1, a2 = u[i, 0], u[i, 1], u[i, 2]
        for k in range(ip[9]):
            gik = g_op[i, k]
            a0 += gik * a_k[k, 0]
            a1 += gik * a_k[k, 1]
            a2 += gik * a_k[k, 2]
        dy[va + 3 * i] = a0
        dy[va + 3 * i + 1] = a1
        dy[va + 3 * i + 2] = a2
    base = 6 * nf
    for i in range(12):
        dy[base + i] = 0.0
    if ip[5] == 0:
        return
    _end_body(y, base, mdl)
    fb, tau, a_n, rhs3, corr = vec[0], vec[8], vec[5], vec[6], vec[7]
    me, a3, tmp = mat[0], mat[1], mat[2]
    c_last = p_last[nf - 1]
    last = va + 3 * (nf - 1)
    for r in range(3):
        rhs3[r] = dy[last + r] + c_last * fb[r]
        for c in range(3):
            a3[r, c] = (1.0 if r == c else 0.0) + c_last * me[r, c]
    _solve3(a3, rhs3, a_n, tmp)
    for r in range(3):
        corr[r] = fb[r] - (me[r, 0] * a_n[0] + me[r, 1] * a_n[1] + me[r, 2] * a_n[2])
    for i in range(nf):
        ci = p_last[i]
        dy[va + 3 * i] += ci * corr[0]
        dy[va + 3 * i + 1] += ci * corr[1]
        dy[va + 3 * i + 2] += ci * corr[2]
    if ip[5] == 2:
        om = y[base:base + 3]
        rot = y[base + 3:base + 12].reshape((3, 3))
        tmp1, tmp2 = vec[2], vec[3]
        _mv(rot, dy[last:last + 3], tmp1, True)
        _cross(rho_c, tmp1, tmp2)
        for c in range(3):
            tmp2[c] = tau[c] - fp[6] * tmp2[c]
        _mv(pi_inv, tmp2, tmp1, False)
        for c in range(3):
            dy[base + c] = tmp1[c]
        for r in range(3):
            for c in range(3):
                # column c of R Omega^ is R (Omega x e_c)
                k1, k2 = (c + 1) % 3, (c + 2) % 3
                dy[base + 3 + 3 * r + c] = rot[r, k1] * om[k2] - rot[r, k2] * om[k1]


@njit(cache=True, inline='always')
def max_strain(mdl):
    """Largest strain over elements (Gauss points for quadratic) of the current X, and its element."""
    ip, fp, x = mdl[0], mdl[1], mdl[12]
    l0 = fp[1]
    worst, where = -1.0, 0
    for e in range(ip[2]):
        if ip[0] == 1:
            d0 = x[e + 1, 0] - x[e, 0]
            d1 = x[e + 1, 1] - x[e, 1]
            d2 = x[e + 1, 2] - x[e, 2]
            eps = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) / l0 - 1.0
        else:
            n0 = 2 * e
            eps = -1.0
            for g in range(2):
                z = -SQRT3_INV if g == 0 else SQRT3_INV
                s0, s1, s2 = z - 0.5, -2.0 * z, z + 0.5
                acc = 0.0
                for c in range(3):
                    lc = 2.0 * (s0 * x[n0, c] + s1 * x[n0 + 1, c] + s2 * x[n0 + 2, c])
                    acc += lc * lc
                eg = np.sqrt(acc) / l0 - 1.0
                if eg > eps or eg != eg:
                    eps = eg
        if eps != eps:
            return eps, e
        if eps > worst:
            worst, where = eps, e
    return worst, where


@njit(cache=True, inline='always')
def _renormalize(y, mdl):
    """Keep the rotation block of y orthonormal: one Newton step of the polar decomposition."""
    ip = mdl[0]
    if ip[5] != 2:
        return
    base = 6 * (ip[4] - ip[3]) + 3
    rot = y[base:base + 9].reshape((3, 3)).copy()
    rot = 1.5 * rot - 0.5 * rot @ (rot.T @ rot)
    for r in range(3):
        for c in range(3):
            y[base + 3 * r + c] = rot[r, c]


@njit(cache=True, inline='always')
def _check(y, mdl):
    """Return (status, element, strain) for the state y just reached by a step.

    Kinematic node positions are those of the last right-hand side call, which both
    steppers make at the time of y.
    """
    total = 0.0
    for i in range(y.size):
        total += y[i]
    if not np.isfinite(total):
        return STATUS_NONFINITE, -1, np.nan
    ip, x = mdl[0], mdl[12]
    f0 = ip[3]
    for i in range(ip[4] - f0):
        x[f0 + i, 0] = y[3 * i]
        x[f0 + i, 1] = y[3 * i + 1]
        x[f0 + i, 2] = y[3 * i + 2]
    eps, e = max_strain(mdl)
    if eps > mdl[1][23]:
        return STATUS_STRAIN, e, eps
    return STATUS_OK, e, eps


@njit(cache=True)
def run_rk4(y0, t0, dt, n_steps, rec_every, mdl):
    """Classic fixed-step RK4 (the thesis's scheme, Sec. 9.1.1), checked after every step.

    Returns (t_rec, y_rec, n_rec, status, t_fail, element, strain).
    """
    n = y0.size
    n_rec_max = n_steps // rec_every + 1
    y_rec = np.empty((n_rec_max, n))
    t_rec = np.empty(n_rec_max)
    y = y0.copy()
    k = np.empty((4, n))
    yt = np.empty(n)
    dy = np.empty(n)
    c_stage = np.array([0.0, 0.5, 0.5, 1.0])
    ip, fp = mdl[0], mdl[1]
    moving = ip[12] == 1
    kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k = mdl[5], mdl[6], mdl[7], mdl[8], mdl[12], mdl[13], mdl[15]
    y_rec[0] = y
    t_rec[0] = t0
    n_rec = 1
    for s in range(n_steps):
        t = t0 + s * dt
        for st in range(4):
            if st == 0:
                for i in range(n):
                    yt[i] = y[i]
            else:
                h = c_stage[st] * dt
                for i in range(n):
                    yt[i] = y[i] + h * k[st - 1, i]
            if moving:
                _kinematic_nodes(t + c_stage[st] * dt, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k)
            rhs(t + c_stage[st] * dt, yt, dy, mdl)
            for i in range(n):
                k[st, i] = dy[i]
        for i in range(n):
            y[i] += dt / 6.0 * (k[0, i] + 2.0 * k[1, i] + 2.0 * k[2, i] + k[3, i])
        _renormalize(y, mdl)
        status, e, eps = _check(y, mdl)
        if status != STATUS_OK:
            return t_rec, y_rec, n_rec, status, t + dt, e, eps
        if (s + 1) % rec_every == 0:
            y_rec[n_rec] = y
            t_rec[n_rec] = t + dt
            n_rec += 1
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
    ip = mdl[0]
    nf = ip[4] - ip[3]
    n = y0.size
    base = 6 * nf
    n_rec_max = n_steps // rec_every + 1
    y_rec = np.empty((n_rec_max, n))
    t_rec = np.empty(n_rec_max)
    y = y0.copy()
    dy = np.empty(n)
    y_rec[0] = y
    t_rec[0] = t0
    n_rec = 1
    fp = mdl[1]
    moving = ip[12] == 1
    kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k = mdl[5], mdl[6], mdl[7], mdl[8], mdl[12], mdl[13], mdl[15]
    for s in range(n_steps + 1):
        t = t0 + s * dt
        if moving:
            _kinematic_nodes(t, ip, fp, kin_idx, kin_pos, kin_vel, kin_acc, x, v, a_k)
        rhs(t, y, dy, mdl)
        if s > 0:
            for i in range(3 * nf):
                y[3 * nf + i] += 0.5 * dt * dy[3 * nf + i]
            for i in range(3):
                y[base + i] += 0.5 * dt * dy[base + i]
            status, e, eps = _check(y, mdl)
            if status != STATUS_OK:
                return t_rec, y_rec, n_rec, status, t, e, eps
            if s % rec_every == 0:
                y_rec[n_rec] = y
                t_rec[n_rec] = t
                n_rec += 1
        if s == n_steps:
            break
        for i in range(3 * nf):
            y[3 * nf + i] += 0.5 * dt * dy[3 * nf + i]
        for i in range(3):
            y[base + i] += 0.5 * dt * dy[base + i]
        for i in range(3 * nf):
            y[i] += dt * y[3 * nf + i]
        if ip[5] == 2:
            rot = _rotation_step(y[base + 3:base + 12].reshape((3, 3)).copy(), y[base:base + 3], dt)
            for r in range(3):
                for c in range(3):
                    y[base + 3 + 3 * r + c] = rot[r, c]
    return t_rec, y_rec, n_rec, STATUS_OK, t0 + n_steps * dt, -1, 0.0


@njit(cache=True)
def node_forces(t, y, mdl):
    """Nodal forces (gravity + elastic + drag) of state y, for tests and statics."""
    _kinematic_of_model(t, mdl)
    _unpack(y, mdl)
    f = mdl[14]
    f[:, :] = mdl[4]
    _elastic_forces(mdl)
    if mdl[0][7] == 1:
        _drag_forces(mdl[0], mdl[1], mdl[12], mdl[13], f)
    return f.copy()


@njit(cache=True)
def unpack_all(t_rec, y_rec, mdl):
    """Node positions and velocities (n, n_all, 3) of recorded states, kinematic ends filled in."""
    n_all = mdl[0][1]
    xs = np.empty((t_rec.size, n_all, 3))
    vs = np.empty((t_rec.size, n_all, 3))
    for r in range(t_rec.size):
        _kinematic_of_model(t_rec[r], mdl)
        _unpack(y_rec[r], mdl)
        xs[r] = mdl[12]
        vs[r] = mdl[13]
    return xs, vs
