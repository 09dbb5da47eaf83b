"""Compiled stepping of the finite-element tether with a moving reel (see :mod:`.fem_reel`).

Lumped-mass linear elements, node 0 at the guide way (kinematic), the last node at the
UAV attachment point (kinematic: prescribed, or carried by the UAV body), symplectic
Euler time stepping. The reel element (element 0, between the guide way and node 1) takes
the deployed length's change; how the mesh follows it is chosen by ``method``:

0 'ale'           the reel element's rest length follows L; material joining node 1's lump
                  brings its momentum (velocity u0 at the guide way); exact split at
                  SPLIT * h, momentum-conserving merge below MERGE * h.
1 'last_element'  only the reel element's rest length changes (MoorDyn-F's DeltaL).
2 'uniform'       every element is reset to L / N each step (MoorDyn-C, KiteModels).
3 'insert'        whole elements of length h are inserted or removed at the reel end when
                  the paid-out length reaches h (the undeployed remainder is massless).

The integer (``st``) and float (``fp``) parameter vectors and the accumulators (``acc``) are
named once, as layouts (``ST_FIELDS``, ``FP_FIELDS``, ``ACC_FIELDS``; :mod:`tether_dynamics.layout`)
that the slot constants are derived from and :class:`~.fem_reel.FemTether` packs them by; the
constants live here because numba freezes them into the cached code.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from tether_dynamics.laws import (AIR_FIELDS, GAUSS, STATUS_FULL, STATUS_NONFINITE, STATUS_OK, STATUS_SHORT,
                                  add_element_drag, kelvin_voigt, quadratic_slope, segment_strain)
from tether_dynamics.layout import offsets, scalars, size
from tether_dynamics.plant.bodies import RP_RADIUS, RS_LENGTH, RS_RATE, body_attach, body_step, reel_step
from tether_dynamics.plant.energies import tether_energies

METHOD_ALE, METHOD_LAST, METHOD_UNIFORM, METHOD_INSERT = range(4)
METHODS = {'ale': METHOD_ALE, 'last_element': METHOD_LAST, 'uniform': METHOD_UNIFORM, 'insert': METHOD_INSERT}
# Linear elements split at 1.5 h and merge below 0.35 h. Not h / 4: a landing's reel-in of a
# slack 2 m tether over 1.665 m elements snapped the 0.42 m reel element taut at 98.6 N (half of
# it the Kelvin-Voigt term, c Ldot / l_r for a reel element l_r), 56 N at 0.35 h on the same
# inputs (tools/plant_replay.py); above 0.35 h the merge's tension step no longer halves with
# the step (test_reel_tension_has_no_step_at_splits_and_merges).
SPLIT = 1.5
MERGE = 0.35
# Quadratic elements split at 1.6 h and merge below h / 2: the short reel element's middle
# node (2/3 of its mass) sets the stable step, so it is kept twice as long as a linear one's.
SPLIT_QUADRATIC = 1.6
MERGE_QUADRATIC = 0.5
ST_FIELDS = scalars('nodes', 'method', 'torque', 'body', 'drag', 'kv', 'splits', 'merges', 'status', 'order')
"""st (int64): nodes in use, method, torque input, dynamic UAV, drag on (with the wind; zero when there is
none), kv on, splits, merges, status (tether_dynamics.laws.STATUS_*), element order (1 linear, 2 quadratic)."""
(ST_NODES, ST_METHOD, ST_TORQUE, ST_BODY, ST_DRAG, ST_KV, ST_SPLITS, ST_MERGES, ST_STATUS, ST_ORDER) = offsets(ST_FIELDS)
ST_SIZE = size(ST_FIELDS)
# What the mesh does after a step (:func:`_mesh_action`).
MESH_KEEP, MESH_SPLIT, MESH_MERGE = 0, 1, 2
FP_FIELDS = (*scalars('ea', 'mu', 'h', 'g', 'kv', 'command', 'thrust', 'pending', 'uav_mass', 'payout', 'command_prev',
                      'owed'), ('acc1', 3), ('acc_uav', 3), ('air', len(AIR_FIELDS)))
"""fp (float64), (name, width): EA (N), mu (kg/m), h (m), g (m/s^2), Kelvin-Voigt c (N s), reel command
(N m or rad/s), thrust (N), pending length ('insert', m), UAV mass (kg), the last step's feed rate into
the reel element (m/s), the reel command of the previous call (a spool-rate command ramps from it over
the call), the rest length a merge took out of the reel element and still owes it (m); node 1's
acceleration in the last step (3, m/s^2: the reel element's inertia); the UAV end's mean acceleration
over the last call (3, m/s^2: its lump's inertia); the air block of drag and wind
(tether_dynamics.laws.AIR_FIELDS)."""
(FP_EA, FP_MU, FP_H, FP_G, FP_KV, FP_COMMAND, FP_THRUST, FP_PENDING, FP_UAV_MASS, FP_PAYOUT, FP_COMMAND_PREV,
 FP_OWED, FP_ACC1, FP_ACC_UAV, FP_AIR) = offsets(FP_FIELDS)
FP_SIZE = size(FP_FIELDS)
# Time constant (s) over which the reel element gets back what a merge took out of it.
PAYBACK = 0.25
ACC_FIELDS = scalars('ends', 'rest', 'mass', 'drag', 'kv', 'reshape', 'jump', 'last_t', 'owed', 'jump_t', 'throughput')
"""acc (float64): energy flows into the deployed tether (J): through the moving ends, the rest-length
change, the mass change of the free lumps (with the inflow's momentum), drag, Kelvin-Voigt dissipation,
and the energy change of mesh splits and merges; then the largest change of the reel tension from one
step to the next (N), the last reel tension (N; NaN before the first step), the rest length merges
took out of the reel element (m, summed), the time of the largest change (s), and the energy
throughput: the integral of the flows' absolute values (J)."""
(ACC_ENDS, ACC_REST, ACC_MASS, ACC_DRAG, ACC_KV, ACC_RESHAPE, ACC_JUMP, ACC_LAST_T, ACC_OWED, ACC_JUMP_T,
 ACC_THROUGHPUT) = offsets(ACC_FIELDS)
ACC_SIZE = size(ACC_FIELDS)


@njit(cache=True)
def _hermite(tab, t_a, t_b, t, pos, vel):
    """Cubic Hermite point of tab = [p_a, v_a, p_b, v_b] over [t_a, t_b] at t."""
    h = t_b - t_a
    u = (t - t_a) / h
    u2, u3 = u * u, u * u * u
    h00, h10, h01, h11 = 2 * u3 - 3 * u2 + 1, u3 - 2 * u2 + u, -2 * u3 + 3 * u2, u3 - u2
    d00, d10, d01, d11 = (6 * u2 - 6 * u) / h, 3 * u2 - 4 * u + 1, (-6 * u2 + 6 * u) / h, 3 * u2 - 2 * u
    for c in range(3):
        pos[c] = h00 * tab[0, c] + h10 * h * tab[1, c] + h01 * tab[2, c] + h11 * h * tab[3, c]
        vel[c] = d00 * tab[0, c] + d10 * tab[1, c] + d01 * tab[2, c] + d11 * tab[3, c]


@njit(cache=True)
def _set_ends(x, v, n, body_on, bs, rho, g_tab, u_tab, t_a, t_b, t, p0, v0, pf, vf):
    """Put the guide way (node 0) and the UAV attachment point (node n - 1) where they are at t:
    the guide way on its Hermite segment, the UAV end on the body or on its Hermite segment.
    """
    _hermite(g_tab, t_a, t_b, t, p0, v0)
    if body_on:
        body_attach(bs, rho, pf, vf)
    else:
        _hermite(u_tab, t_a, t_b, t, pf, vf)
    for c in range(3):
        x[0, c], v[0, c] = p0[c], v0[c]
        x[n - 1, c], v[n - 1, c] = pf[c], vf[c]


@njit(cache=True)
def element_tensions(x, v, rest, n, fp, kv_on, u0, out):
    """Tension of each element (:func:`tether_dynamics.laws.kelvin_voigt`) into out[:n - 1];
    element 0's strain rate uses the material velocity u0 at the guide way.
    """
    ea, c_kv = fp[FP_EA], fp[FP_KV]
    for e in range(n - 1):
        w0 = w1 = w2 = 0.0
        if kv_on:
            if e == 0:
                w0, w1, w2 = v[1, 0] - u0[0], v[1, 1] - u0[1], v[1, 2] - u0[2]
            else:
                w0, w1, w2 = v[e + 1, 0] - v[e, 0], v[e + 1, 1] - v[e, 1], v[e + 1, 2] - v[e, 2]
        eps, rate = segment_strain(x[e + 1, 0] - x[e, 0], x[e + 1, 1] - x[e, 1], x[e + 1, 2] - x[e, 2],
                                   w0, w1, w2, 1.0 / rest[e])[1:]
        out[e] = kelvin_voigt(eps, rate, ea, c_kv, True)[0]


@njit(cache=True)
def _drag(x, v, rest, n, order, fp, f):
    """Air drag and wind on each element (:func:`tether_dynamics.laws.add_element_drag`) into f."""
    for e in range((n - 1) // order):
        add_element_drag(x, v, order * e, order, rest[e], fp, FP_AIR, f)


@njit(cache=True)
def lump(rest, n, order, mu, i):
    """Lumped mass of node i (kg): half of each adjacent linear element; of a quadratic element
    (row sums of its consistent mass matrix, Eq. D.12) 1/6 at each end node and 2/3 at the
    middle node.
    """
    if order == 1:
        return 0.5 * mu * ((rest[i - 1] if i > 0 else 0.0) + (rest[i] if i < n - 1 else 0.0))
    if i % 2 == 1:
        return 2.0 / 3.0 * mu * rest[(i - 1) // 2]
    e = i // 2
    return mu / 6.0 * ((rest[e - 1] if e > 0 else 0.0) + (rest[e] if e < (n - 1) // 2 else 0.0))


@njit(cache=True)
def _gauss_stretch(x, rest, e, gi, r):
    """Tangent r = dr/ds (s the rest-length coordinate; |r| is the stretch) at Gauss point gi
    of quadratic element e, into r.
    """
    k = 2.0 / rest[e]
    sa, sb, sc = quadratic_slope(GAUSS[gi])
    a, b, c = sa * k, sb * k, sc * k
    j = 2 * e
    for d in range(3):
        r[d] = a * x[j, d] + b * x[j + 1, d] + c * x[j + 2, d]


@njit(cache=True)
def energy(x, v, rest, n, fp, order):
    """Mechanical energy of the deployed tether as the balance counts it (J): kinetic energy
    of the free nodes' lumps, strain energy (the quadratic element's by 2-point Gauss, as its
    forces), and the gravitational energy of the lumps (every lump, the end ones included).
    """
    mu, ea, g = fp[FP_MU], fp[FP_EA], fp[FP_G]
    e_sum = 0.0
    if order == 1:
        for e in range(n - 1):
            d0 = x[e + 1, 0] - x[e, 0]
            d1 = x[e + 1, 1] - x[e, 1]
            d2 = x[e + 1, 2] - x[e, 2]
            eps = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) / rest[e] - 1.0
            if eps > 0.0:
                e_sum += 0.5 * ea * rest[e] * eps * eps
    else:
        r = np.empty(3)
        for e in range((n - 1) // 2):
            for gi in range(2):
                _gauss_stretch(x, rest, e, gi, r)
                eps = np.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) - 1.0
                if eps > 0.0:
                    e_sum += 0.25 * ea * rest[e] * eps * eps
    for i in range(n):
        m = lump(rest, n, order, mu, i)
        e_sum += m * g * x[i, 2]
        if 0 < i < n - 1:
            e_sum += 0.5 * m * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
    return e_sum


@njit(cache=True)
def exit_tension(x, rest, tens, fp):
    """Tension where the tether leaves the guide way (N): the reel element's (uniform)
    tension carried from its midpoint to its start by the weight and inertia of the
    half-element, T(0) = T_0 - mu (g e_z + a . e) l_0 / 2 (e the element's unit vector away
    from the guide way, a node 1's acceleration in the last step).
    """
    d0 = np.sqrt((x[1, 0] - x[0, 0]) ** 2 + (x[1, 1] - x[0, 1]) ** 2 + (x[1, 2] - x[0, 2]) ** 2)
    if tens[0] <= 0.0 or d0 == 0.0:
        return 0.0
    along = 0.0
    for c in range(3):
        along += fp[FP_ACC1 + c] * (x[1, c] - x[0, c]) / d0
    t = tens[0] - 0.5 * fp[FP_MU] * (fp[FP_G] * (x[1, 2] - x[0, 2]) / d0 + along) * rest[0]
    return t if t > 0.0 else 0.0


@njit(cache=True)
def _split(x, v, rest, st, fp, u0):
    """Cut the reel element at rest length l_a = rest[0] - h from the guide way.

    Mass and momentum: the new node's velocity is the material velocity interpolated at the
    mass fraction l_a / l_0, so the lumps' momentum is unchanged. Geometry: the node lies on
    the element's chord, so the tether's shape is unchanged; where along the chord is chosen
    so the two new elements carry the tension gradient of the tether's weight and inertia
    (T_a - T_b = -mu (g e_z + a . e) (l_a + l_b) / 2, a node 1's acceleration, mean strain
    kept): the exit tension
    :func:`exit_tension` is then the same before and after the cut.
    """
    n = st[ST_NODES]
    if n + 1 > x.shape[0]:
        st[ST_STATUS] = STATUS_FULL
        return
    h = fp[FP_H]
    l0 = rest[0]
    la, lb = l0 - h, h
    lam = la / l0
    chord = np.sqrt((x[1, 0] - x[0, 0]) ** 2 + (x[1, 1] - x[0, 1]) ** 2 + (x[1, 2] - x[0, 2]) ** 2)
    eps = chord / l0 - 1.0
    frac = lam
    if eps > 0.0 and chord > 0.0:
        along = 0.0
        for c in range(3):
            along += fp[FP_ACC1 + c] * (x[1, c] - x[0, c]) / chord
        grad = -fp[FP_MU] * (fp[FP_G] * (x[1, 2] - x[0, 2]) / chord + along)
        diff = grad * 0.5 * (la + lb) / fp[FP_EA]
        eps_a, eps_b = eps + diff * lb / l0, eps - diff * la / l0
        if eps_a > 0.0 and eps_b > 0.0:
            frac = la * (1.0 + eps_a) / chord
    for i in range(n, 1, -1):
        x[i] = x[i - 1]
        v[i] = v[i - 1]
    for e in range(n - 1, 0, -1):
        rest[e] = rest[e - 1]
    for c in range(3):
        x[1, c] = (1.0 - frac) * x[0, c] + frac * x[2, c]
        v[1, c] = (1.0 - lam) * u0[c] + lam * v[2, c]
    rest[1] = lb
    rest[0] = la
    st[ST_NODES] = n + 1
    st[ST_SPLITS] += 1


@njit(cache=True)
def _merge(x, v, rest, st, fp, u0_old, v0, payout, keep_strain):
    """Join the reel element to its neighbour: node 1 is removed and node 2's velocity keeps
    the momentum of the three lumps involved (u0 from the joined element after).

    With ``keep_strain`` the joined element keeps the two elements' rest-length-weighted
    mean strain: where node 1 was a kink, the straight element is shorter than the kinked
    path, and the difference of rest length (at that strain) is taken out of it, to be fed
    back into the reel element smoothly over the next PAYBACK seconds (the caller keeps it,
    as deployed mass at the guide way, meanwhile): the tension stays continuous, the mass
    and the deployed length stay exact. Returns the rest length taken out (m).
    """
    n = st[ST_NODES]
    mu = fp[FP_MU]
    l0, l1, l2 = rest[0], rest[1], rest[2] if n > 3 else 0.0
    c0 = np.sqrt((x[1, 0] - x[0, 0]) ** 2 + (x[1, 1] - x[0, 1]) ** 2 + (x[1, 2] - x[0, 2]) ** 2)
    c1 = np.sqrt((x[2, 0] - x[1, 0]) ** 2 + (x[2, 1] - x[1, 1]) ** 2 + (x[2, 2] - x[1, 2]) ** 2)
    chord = np.sqrt((x[2, 0] - x[0, 0]) ** 2 + (x[2, 1] - x[0, 1]) ** 2 + (x[2, 2] - x[0, 2]) ** 2)
    mean_strain = (c0 + c1) / (l0 + l1) - 1.0
    # Momentum before: lumps of node 0 (material velocity u0), node 1, node 2.
    p = np.empty(3)
    for c in range(3):
        p[c] = 0.5 * mu * l0 * u0_old[c] + 0.5 * mu * (l0 + l1) * v[1, c] + 0.5 * mu * (l1 + l2) * v[2, c]
    for i in range(1, n - 1):
        x[i] = x[i + 1]
        v[i] = v[i + 1]
    merged = l0 + l1
    owed = 0.0
    if keep_strain and mean_strain > 0.0:
        kept = chord / (1.0 + mean_strain)
        if kept < merged:
            owed = merged - kept
            merged = kept
    rest[0] = merged
    for e in range(1, n - 2):
        rest[e] = rest[e + 1]
    st[ST_NODES] = n - 1
    st[ST_MERGES] += 1
    if n - 1 <= 2:
        return owed
    lr = rest[0]
    w1 = 0.5 * mu * (lr + l2)
    for c in range(3):
        u0_new = v0[c] + payout * (x[1, c] - x[0, c]) / lr
        p[c] -= 0.5 * mu * owed * u0_old[c]
        v[1, c] = (p[c] - 0.5 * mu * lr * u0_new) / w1
    return owed


@njit(cache=True)
def guide_tangent(x, rest, order, out):
    """dr/ds at the guide way (s the rest-length coordinate; its length is the stretch):
    (x1 - x0) / l0 on a linear reel element, (-3 x0 + 4 x1 - x2) / l0 on a quadratic one.
    """
    for c in range(3):
        if order == 1:
            out[c] = (x[1, c] - x[0, c]) / rest[0]
        else:
            out[c] = (-3.0 * x[0, c] + 4.0 * x[1, c] - x[2, c]) / rest[0]


@njit(cache=True)
def quadratic_forces(x, v, rest, n, fp, kv_on, u0, tens, tkv, f, tangents):
    """Quadratic elements, 2-point Gauss (Eq. D.8-D.10): the tension at each Gauss point into
    tens[2 e + g] (its Kelvin-Voigt part into tkv), the elastic and damping forces added into
    f, f_k -= T_g e_g dS_k/dzeta. Element 0's strain rate uses the material velocity u0 at the
    guide way. Each Gauss point's tangent r = dr/ds and stretch |r| go into
    tangents[2 e + g, 0:3] and [.., 3], which the step's energy flows read.
    """
    ea, c_kv = fp[FP_EA], fp[FP_KV]
    for e in range((n - 1) // 2):
        j = 2 * e
        k = 2.0 / rest[e]
        for gi in range(2):
            sa, sb, sc = quadratic_slope(GAUSS[gi])
            p = 2 * e + gi
            r = tangents[p]
            _gauss_stretch(x, rest, e, gi, r)
            w0 = w1 = w2 = 0.0
            if kv_on:
                va = u0 if e == 0 else v[j]
                w0 = k * (sa * va[0] + sb * v[j + 1, 0] + sc * v[j + 2, 0])
                w1 = k * (sa * va[1] + sb * v[j + 1, 1] + sc * v[j + 2, 1])
                w2 = k * (sa * va[2] + sb * v[j + 1, 2] + sc * v[j + 2, 2])
            lam, eps, rate = segment_strain(r[0], r[1], r[2], w0, w1, w2, 1.0)
            r[3] = lam
            t, tkv[p] = kelvin_voigt(eps, rate, ea, c_kv, True)
            tens[p] = t
            if t == 0.0:
                continue
            for c in range(3):
                fc = t * r[c] / lam
                f[j, c] -= fc * sa
                f[j + 1, c] -= fc * sb
                f[j + 2, c] -= fc * sc


@njit(cache=True)
def quadratic_exit_force(f0, m0, fp, out):
    """Force of quadratic elements on the guide way, into out, and its size (the exit tension),
    N: the elements' internal force on node 0 (their Gauss-point tensions extrapolated to
    zeta = -1, Eq. D.8) less the weight and inertia of node 0's lump (mu l_0 / 6, moving
    with node 1's acceleration of the last step). The tangent's own length at zeta = -1 is
    not used: on a curved element it overstates the stretch by about (kappa l_0)^2 / 8.
    """
    if f0[0] == 0.0 and f0[1] == 0.0 and f0[2] == 0.0:
        out[:] = 0.0
        return 0.0
    for c in range(3):
        out[c] = f0[c] - m0 * fp[FP_ACC1 + c]
    out[2] -= m0 * fp[FP_G]
    return np.sqrt(out[0] ** 2 + out[1] ** 2 + out[2] ** 2)


@njit(cache=True)
def _quadratic_at(xa, xb, xc, z, out):
    """The quadratic field through xa, xb, xc (zeta = -1, 0, 1) at zeta."""
    sa, sb, sc = 0.5 * (z * z - z), 1.0 - z * z, 0.5 * (z * z + z)
    for c in range(3):
        out[c] = sa * xa[c] + sb * xb[c] + sc * xc[c]


@njit(cache=True)
def _reparametrised(xa, xb, xc, l0, zetas, out):
    """Where on the parabola through xa, xb, xc the material points at ``zetas`` lie if the
    stretch along the element is the one its quadrature sees (linear through the two Gauss
    points' stretches): the parameters zeta' (into out) at which the parabola's arc length
    is that stretch's integral, scaled to the parabola's length. Equal to zetas where the
    parabola's speed is itself linear (a straight element, a hanging tether); on a coarse,
    deeply curved element it keeps the new elements' Gauss strains at the old ones instead
    of exposing the stretch the old quadrature did not see.
    """
    m = 256
    zg = np.linspace(-1.0, 1.0, m + 1)
    arc = np.zeros(m + 1)
    believed = np.zeros(m + 1)
    lam = np.empty(2)
    for gi in range(2):
        sa, sb, sc = quadratic_slope(GAUSS[gi])
        sq = 0.0
        for c in range(3):
            d = sa * xa[c] + sb * xb[c] + sc * xc[c]
            sq += d * d
        lam[gi] = 2.0 * np.sqrt(sq) / l0
    slope = (lam[1] - lam[0]) / (GAUSS[1] - GAUSS[0])
    # A partly slack element (a Gauss point at stretch <= 1): its line through the Gauss points,
    # extrapolated past the taut one, put stretch the element never had on the new elements
    # (a split of a 0.889 / 1.000 reel element: 570 N in a tether carrying 3 N); held between them.
    low, high = min(lam[0], lam[1]), max(lam[0], lam[1])
    partly_slack = low <= 1.0
    speed_prev, bel_prev = 0.0, 0.0
    for i in range(m + 1):
        z = zg[i]
        sa, sb, sc = quadratic_slope(z)
        sq = 0.0
        for c in range(3):
            d = sa * xa[c] + sb * xb[c] + sc * xc[c]
            sq += d * d
        speed = np.sqrt(sq)
        bel = lam[0] + slope * (z - GAUSS[0])
        if partly_slack:
            bel = min(max(bel, low), high)
        bel = max(bel, 1e-3)
        if i > 0:
            arc[i] = arc[i - 1] + 0.5 * (speed + speed_prev) * (zg[i] - zg[i - 1])
            believed[i] = believed[i - 1] + 0.5 * (bel + bel_prev) * (zg[i] - zg[i - 1])
        speed_prev, bel_prev = speed, bel
    for k in range(zetas.size):
        target = np.interp(zetas[k], zg, believed) / believed[m] * arc[m]
        out[k] = np.interp(target, arc, zg)


@njit(cache=True)
def _split_quadratic(x, v, rest, st, fp, u0):
    """Cut the quadratic reel element at rest length l_a = l_0 - h from the guide way, into
    two elements on the old element's parabola: the new nodes sit where the material points
    at zeta_c = 2 l_a / l_0 - 1 and at the two new middles lie (:func:`_reparametrised`:
    where the old element's stretch is linear, an exact subdivision - shape, strain field and
    exit force unchanged), with the velocity field there (with the material velocity u0 at
    the guide way). The momentum of the lumps (Simpson's rule on the velocity field) is then
    restored exactly by a uniform correction of the three new nodes' velocities.
    """
    n = st[ST_NODES]
    if n + 2 > x.shape[0]:
        st[ST_STATUS] = STATUS_FULL
        return
    mu = fp[FP_MU]
    l0 = rest[0]
    la = l0 - fp[FP_H]
    lb = fp[FP_H]
    zc = 2.0 * la / l0 - 1.0
    xa, xb, xc = x[0].copy(), x[1].copy(), x[2].copy()
    va, vb, vc = u0.copy(), v[1].copy(), v[2].copy()
    w2_old = mu * l0 / 6.0
    p = np.empty(3)
    for c in range(3):
        p[c] = 2.0 / 3.0 * mu * l0 * vb[c] + w2_old * vc[c] + mu * l0 / 6.0 * va[c]
    for i in range(n - 1, 1, -1):
        x[i + 2] = x[i]
        v[i + 2] = v[i]
    for e in range((n - 1) // 2 - 1, 0, -1):
        rest[e + 1] = rest[e]
    material = np.array([0.5 * (zc - 1.0), zc, 0.5 * (zc + 1.0)])
    where = np.empty(3)
    _reparametrised(xa, xb, xc, l0, material, where)
    for node in range(3):
        _quadratic_at(xa, xb, xc, where[node], x[node + 1])
        _quadratic_at(va, vb, vc, where[node], v[node + 1])
    rest[0] = la
    rest[1] = lb
    masses = np.array([2.0 / 3.0 * mu * la, mu * (la + lb) / 6.0, 2.0 / 3.0 * mu * lb])
    for c in range(3):
        p_new = mu * la / 6.0 * va[c] + mu * lb / 6.0 * vc[c]
        for node in range(3):
            p_new += masses[node] * v[node + 1, c]
        dv = (p[c] - p_new) / (masses[0] + masses[1] + masses[2])
        for node in range(3):
            v[node + 1, c] += dv
    st[ST_NODES] = n + 2
    st[ST_SPLITS] += 1


@njit(cache=True)
def _merge_quadratic(x, v, rest, st, fp, u0, v0, feed):
    """Join the quadratic reel element (l_0 < MERGE_QUADRATIC h) to its neighbour. The joined
    element's middle node is the material point at L / 2 (L = l_0 + l_1, inside the old
    second element, placed on it by :func:`_reparametrised`): the joined parabola runs through
    three points of the old shape, so its stretch - and the tension - is the old one to the
    shape's resolution, and a tether whose shape is one parabola over both elements (a
    hanging tether) is reproduced exactly. The middle node's velocity keeps the momentum of
    the lumps involved (node 0's lump with the material velocity at the guide way, before
    and after); mass is exact.
    """
    n = st[ST_NODES]
    l0, l1 = rest[0], rest[1]
    big = l0 + l1
    p = np.empty(3)
    for c in range(3):
        p[c] = (l0 / 6.0 * u0[c] + 2.0 / 3.0 * l0 * v[1, c] + (l0 + l1) / 6.0 * v[2, c]
                + 2.0 / 3.0 * l1 * v[3, c] + l1 / 6.0 * v[4, c])
    where = np.empty(1)
    _reparametrised(x[2].copy(), x[3].copy(), x[4].copy(), l1, np.array([2.0 * (0.5 * big - l0) / l1 - 1.0]), where)
    xm = np.empty(3)
    _quadratic_at(x[2], x[3], x[4], where[0], xm)
    for c in range(3):
        x[1, c] = xm[c]
        u_new = v0[c] + feed * (-3.0 * x[0, c] + 4.0 * xm[c] - x[4, c]) / big
        v[1, c] = (p[c] - big / 6.0 * u_new - big / 6.0 * v[4, c]) / (2.0 / 3.0 * big)
    for i in range(2, n - 2):
        x[i] = x[i + 2]
        v[i] = v[i + 2]
    rest[0] = big
    for e in range(1, (n - 1) // 2 - 1):
        rest[e] = rest[e + 1]
    st[ST_NODES] = n - 2
    st[ST_MERGES] += 1


@njit(cache=True)
def advance(x, v, rest, st, fp, rs, rp, g_tab, u_tab, t_a, t_b, n_sub, bs, inertia, inertia_inv, rho, torque, acc):
    """Advance the tether, the winch and (if dynamic) the UAV from t_a to t_b in n_sub steps.

    Each step is a sequence of named stages, all evaluated at the step's start as the forces
    are: the ends (:func:`_set_ends`), the material velocity at the guide way, the element
    forces, the energy flows through the ends, weight and drag, the winch, the UAV body,
    the free nodes' velocities with their mass rates, the power of the rest-length change and
    of the Kelvin-Voigt damping, then the positions, the mesh following the deployed length,
    and its splits and merges.
    """
    dt = (t_b - t_a) / n_sub
    order, method, kv_on = st[ST_ORDER], st[ST_METHOD], st[ST_KV] == 1
    cap = x.shape[0]
    f = np.zeros((cap, 3))
    drag = np.zeros((cap, 3))
    tens = np.zeros(cap)
    tkv = np.zeros(cap)
    tangents = np.zeros((cap, 4))
    mesh = np.zeros(3)
    p0, v0, pf, vf, u0, tan = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    force_uav, force_reel, first = np.empty(3), np.empty(3), np.empty(3)
    feed = rp[RP_RADIUS] * rs[RS_RATE]
    for k in range(n_sub):
        t = t_a + k * dt
        n = st[ST_NODES]
        _set_ends(x, v, n, st[ST_BODY] == 1, bs, rho, g_tab, u_tab, t_a, t_b, t, p0, v0, pf, vf)
        if k == 0:
            first[:] = vf
        _material_velocity(x, rest, order, method, feed, v0, tan, u0)
        t_exit = _element_forces(x, v, rest, n, order, kv_on, fp, u0, tens, tkv, f, tangents, force_reel)
        _note_tension_jump(acc, t_exit, t)
        _end_flows(f, rest, n, order, fp, v0, vf, force_uav, acc, dt)
        _weight_and_drag(x, v, rest, n, order, st, fp, f, drag, acc, dt)
        feed = _winch(st, fp, rs, rp, t_exit, k, n_sub, dt)
        if st[ST_BODY] == 1:
            body_mass = fp[FP_UAV_MASS] + lump(rest, n, order, fp[FP_MU], n - 1)
            body_step(bs, body_mass, inertia, inertia_inv, rho, fp[FP_THRUST], torque, force_uav, fp[FP_G], dt)
        _accelerate(v, rest, n, order, method, fp, feed, u0, f, acc, dt)
        _rest_change_flow(x, rest, n, order, method, fp, feed, tens, tkv, tangents, mesh, acc, dt)
        if kv_on:
            _damping_flow(x, v, rest, n, order, fp, tens, tkv, tangents, acc, dt)
        _move_nodes(x, v, n, order, method, mesh, dt)
        if not _follow_length(rest, st, fp, rs, n, order, feed, dt):
            return
        action = _mesh_action(rest, st, fp, n, order)
        if action != MESH_KEEP:
            _remesh(x, v, rest, st, fp, acc, n, order, feed, u0, v0, action)
        if st[ST_STATUS] != STATUS_OK:
            return
        for c in range(3):
            if not np.isfinite(x[1, c] + v[1, c]):
                st[ST_STATUS] = STATUS_NONFINITE
                return
    _set_ends(x, v, st[ST_NODES], st[ST_BODY] == 1, bs, rho, g_tab, u_tab, t_a, t_b, t_b, p0, v0, pf, vf)
    for c in range(3):
        fp[FP_ACC_UAV + c] = (vf[c] - first[c]) / (t_b - t_a)
    if not _all_finite(x, v, rest, st[ST_NODES], order, bs, rs, acc):
        st[ST_STATUS] = STATUS_NONFINITE


@njit(cache=True, _nrt=False)
def _material_velocity(x, rest, order, method, feed, v0, tan, u0):
    """The material velocity at the guide way into u0: the guide way's plus the payout along the reel element."""
    guide_tangent(x, rest, order, tan)
    for c in range(3):
        u0[c] = v0[c]
        if method == METHOD_ALE:
            u0[c] += feed * tan[c]


@njit(cache=True, _nrt=False)
def _element_forces(x, v, rest, n, order, kv_on, fp, u0, tens, tkv, f, tangents, force_reel):
    """The elements' elastic and damping forces into f[:n] (zeroed first), their tensions into
    tens (quadratic: per Gauss point, damping parts into tkv); returns the tension at the guide way.
    """
    f[:n] = 0.0
    if order == 2:
        quadratic_forces(x, v, rest, n, fp, kv_on, u0, tens, tkv, f, tangents)
        return quadratic_exit_force(f[0], lump(rest, n, 2, fp[FP_MU], 0), fp, force_reel)
    element_tensions(x, v, rest, n, fp, kv_on, u0, tens)
    t_exit = exit_tension(x, rest, tens, fp)
    for e in range(n - 1):
        if tens[e] == 0.0:
            continue
        d = np.sqrt((x[e + 1, 0] - x[e, 0]) ** 2 + (x[e + 1, 1] - x[e, 1]) ** 2
                    + (x[e + 1, 2] - x[e, 2]) ** 2)
        q = tens[e] / d
        for c in range(3):
            fc = q * (x[e + 1, c] - x[e, c])
            f[e, c] += fc
            f[e + 1, c] -= fc
    return t_exit


@njit(cache=True, _nrt=False)
def _note_tension_jump(acc, t_exit, t):
    """Keep the largest change of the guide-way tension from one step to the next, and its time."""
    if np.isfinite(acc[ACC_LAST_T]) and abs(t_exit - acc[ACC_LAST_T]) > acc[ACC_JUMP]:
        acc[ACC_JUMP] = abs(t_exit - acc[ACC_LAST_T])
        acc[ACC_JUMP_T] = t
    acc[ACC_LAST_T] = t_exit


@njit(cache=True, _nrt=False)
def _end_flows(f, rest, n, order, fp, v0, vf, force_uav, acc, dt):
    """The energy flow through the moving ends: the tether's forces on them, and the
    gravitational energy of the kinematic end lumps (part of the counted potential energy);
    the elements' force on the UAV end's node into force_uav. A dynamic UAV carries that node's
    lump: its weight and inertia are the body's (``advance`` adds the lump to the body's mass;
    the lump's moments about the centre of mass, of its weight and of its inertia at the
    attachment offset, are left out).
    """
    mu, g = fp[FP_MU], fp[FP_G]
    m_first, m_last = lump(rest, n, order, mu, 0), lump(rest, n, order, mu, n - 1)
    p_ends = g * (m_first * v0[2] + m_last * vf[2])
    for c in range(3):
        p_ends -= f[0, c] * v0[c] + f[n - 1, c] * vf[c]
        force_uav[c] = f[n - 1, c]
    acc[ACC_ENDS] += dt * p_ends
    acc[ACC_THROUGHPUT] += dt * abs(p_ends)


@njit(cache=True, _nrt=False)
def _weight_and_drag(x, v, rest, n, order, st, fp, f, drag, acc, dt):
    """The lumps' weight and (if on) the air drag on the free nodes into f, with drag's power."""
    mu, g = fp[FP_MU], fp[FP_G]
    for i in range(n):
        f[i, 2] -= lump(rest, n, order, mu, i) * g
    if st[ST_DRAG] != 1:
        return
    drag[:n] = 0.0
    _drag(x, v, rest, n, order, fp, drag)
    p_drag = 0.0
    for i in range(1, n - 1):
        for c in range(3):
            f[i, c] += drag[i, c]
            p_drag += drag[i, c] * v[i, c]
    acc[ACC_DRAG] += dt * p_drag
    acc[ACC_THROUGHPUT] += dt * abs(p_drag)


@njit(cache=True, _nrt=False)
def _winch(st, fp, rs, rp, t_exit, k, n_sub, dt):
    """Step the winch (a spool-rate command ramps over the call); returns the feed rate into the
    reel element: the payout plus what a merge still owes it.
    """
    command = fp[FP_COMMAND]
    if st[ST_TORQUE] == 0:
        command = fp[FP_COMMAND_PREV] + (command - fp[FP_COMMAND_PREV]) * (k + 1) / n_sub
    payout = reel_step(rs, rp, st[ST_TORQUE] == 1, command, t_exit, dt)
    payback = fp[FP_OWED] * min(dt / PAYBACK, 1.0)
    fp[FP_OWED] -= payback
    feed = payout + payback / dt
    fp[FP_PAYOUT] = feed
    return feed


@njit(cache=True, _nrt=False)
def _mass_rate(i, n_el, order, method, mu, feed):
    """The rate of free node i's lump mass from the reel element's rest-length rate (its lumps' shares)."""
    if method == METHOD_UNIFORM:
        return mu * feed / n_el
    if method == METHOD_ALE or method == METHOD_LAST:
        if order == 1:
            return 0.5 * mu * feed if i == 1 else 0.0
        return 2.0 / 3.0 * mu * feed if i == 1 else (mu * feed / 6.0 if i == 2 else 0.0)
    return 0.0


@njit(cache=True, _nrt=False)
def _accelerate(v, rest, n, order, method, fp, feed, u0, f, acc, dt):
    """The free nodes' velocities from their forces, with the inflowing material's momentum
    ('ale'), and the power of their mass change; node 1's acceleration into fp.
    """
    mu = fp[FP_MU]
    n_el = (n - 1) // order
    for i in range(1, n - 1):
        m = lump(rest, n, order, mu, i)
        mdot = _mass_rate(i, n_el, order, method, mu, feed)
        p_mass = 0.5 * mdot * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        for c in range(3):
            a = f[i, c] / m
            if method == METHOD_ALE and mdot != 0.0:
                flux = mdot * (u0[c] - v[i, c])
                a += flux / m
                p_mass += flux * v[i, c]
            v[i, c] += dt * a
            if i == 1:
                fp[FP_ACC1 + c] = a
        acc[ACC_MASS] += dt * p_mass
        acc[ACC_THROUGHPUT] += dt * abs(p_mass)


@njit(cache=True, _nrt=False)
def _rest_change_flow(x, rest, n, order, method, fp, feed, tens, tkv, tangents, mesh, acc, dt):
    """The elastic and gravitational energy released by the rest-length change at fixed nodes;
    for quadratic elements, the reel element's middle-node mesh velocity into mesh.
    """
    ea, mu, g = fp[FP_EA], fp[FP_MU], fp[FP_G]
    n_el = (n - 1) // order
    p_rest = 0.0
    if order == 1:
        for e in range(n_el):
            if method == METHOD_UNIFORM:
                ldot = feed / n_el
            elif (method == METHOD_ALE or method == METHOD_LAST) and e == 0:
                ldot = feed
            else:
                continue
            length = np.sqrt((x[e + 1, 0] - x[e, 0]) ** 2 + (x[e + 1, 1] - x[e, 1]) ** 2
                             + (x[e + 1, 2] - x[e, 2]) ** 2)
            eps = length / rest[e] - 1.0
            if eps > 0.0:
                p_rest -= ea * eps * (1.0 + 0.5 * eps) * ldot
            p_rest += mu * ldot * g * 0.5 * (x[e, 2] + x[e + 1, 2])
    else:
        for gi in range(2):
            eps = tangents[gi, 3] - 1.0
            if eps > 0.0:
                p_rest -= 0.5 * ea * eps * (1.0 + 0.5 * eps) * feed
        p_rest += mu * feed * g * (x[0, 2] / 6.0 + 2.0 / 3.0 * x[1, 2] + x[2, 2] / 6.0)
        # The reel element's middle node stays at its middle: it moves through the material
        # by -Ldot / 2 along dr/ds (mesh velocity = material velocity - Ldot / 2 r'(0)); the
        # elastic and gravity forces' work on that motion is part of this flow.
        for c in range(3):
            mesh[c] = -0.5 * feed * (x[2, c] - x[0, c]) / rest[0]
            p_rest -= lump(rest, n, order, mu, 1) * g * mesh[c] if c == 2 else 0.0
        for gi in range(2):
            rg = tangents[gi]
            elastic = tens[gi] - tkv[gi]
            if tens[gi] > 0.0:
                for c in range(3):
                    p_rest += elastic * rg[c] / rg[3] * 2.0 * GAUSS[gi] * mesh[c]
    acc[ACC_REST] += dt * p_rest
    acc[ACC_THROUGHPUT] += dt * abs(p_rest)


@njit(cache=True, _nrt=False)
def _damping_flow(x, v, rest, n, order, fp, tens, tkv, tangents, acc, dt):
    """Kelvin-Voigt dissipation: the damping tension's power on the nodes' velocities."""
    n_el = (n - 1) // order
    p_kv = 0.0
    if order == 1:
        for e in range(n_el):
            tk = tens[e]
            length = np.sqrt((x[e + 1, 0] - x[e, 0]) ** 2 + (x[e + 1, 1] - x[e, 1]) ** 2
                             + (x[e + 1, 2] - x[e, 2]) ** 2)
            eps = length / rest[e] - 1.0
            if tk > 0.0 and eps > 0.0:
                tk -= fp[FP_EA] * eps
                w = 0.0
                for c in range(3):
                    w += (x[e + 1, c] - x[e, c]) / length * (v[e + 1, c] - v[e, c])
                p_kv -= tk * w
    else:
        for e in range(n_el):
            j = 2 * e
            for gi in range(2):
                tk = tkv[2 * e + gi]
                if tens[2 * e + gi] == 0.0 or tk == 0.0:
                    continue
                sa, sb, sc = quadratic_slope(GAUSS[gi])
                rg = tangents[2 * e + gi]
                w = 0.0
                for c in range(3):
                    w += rg[c] / rg[3] * (sa * v[j, c] + sb * v[j + 1, c] + sc * v[j + 2, c])
                p_kv -= tk * w
    acc[ACC_KV] += dt * p_kv
    acc[ACC_THROUGHPUT] += dt * abs(p_kv)


@njit(cache=True, _nrt=False)
def _move_nodes(x, v, n, order, method, mesh, dt):
    """The free nodes' positions from their new velocities (symplectic Euler), and for
    quadratic 'ale' the reel element's middle node's mesh motion.
    """
    for i in range(1, n - 1):
        for c in range(3):
            x[i, c] += dt * v[i, c]
    if order == 2 and method == METHOD_ALE:
        for c in range(3):
            x[1, c] += dt * mesh[c]


@njit(cache=True, _nrt=False)
def _follow_length(rest, st, fp, rs, n, order, feed, dt):
    """The mesh follows the deployed length by its method; False (status SHORT) when the reel
    element's rest length reached zero.
    """
    method = st[ST_METHOD]
    n_el = (n - 1) // order
    if method == METHOD_ALE or method == METHOD_LAST:
        rest[0] += dt * feed
        if rest[0] < 1e-6 * fp[FP_H]:
            st[ST_STATUS] = STATUS_SHORT
            return False
    elif method == METHOD_UNIFORM:
        length_now = rs[RS_LENGTH]
        for e in range(n_el):
            rest[e] = length_now / n_el
    else:
        fp[FP_PENDING] += dt * feed
    return True


@njit(cache=True, _nrt=False)
def _mesh_action(rest, st, fp, n, order):
    """What the mesh does after this step: MESH_KEEP, MESH_SPLIT (the reel element grew past its
    split length, or 'insert' has a whole element pending) or MESH_MERGE (it shrank below its
    merge length, or 'insert' owes a whole element).
    """
    method, h = st[ST_METHOD], fp[FP_H]
    if method == METHOD_ALE:
        if rest[0] > (SPLIT if order == 1 else SPLIT_QUADRATIC) * h:
            return MESH_SPLIT
        if rest[0] < (MERGE if order == 1 else MERGE_QUADRATIC) * h and (n - 1) // order > 1:
            return MESH_MERGE
    elif method == METHOD_INSERT:
        if fp[FP_PENDING] >= h:
            return MESH_SPLIT
        if fp[FP_PENDING] <= -h and n > 3:
            return MESH_MERGE
    return MESH_KEEP


@njit(cache=True)
def _remesh(x, v, rest, st, fp, acc, n, order, feed, u0, v0, action):
    """Split or merge the reel element ('ale'), or insert or remove a whole element at the reel
    ('insert'), as :func:`_mesh_action` says; the tether's energy change by it into the reshape flow.
    """
    h = fp[FP_H]
    e_before = energy(x, v, rest, n, fp, order)
    if st[ST_METHOD] == METHOD_ALE:
        if action == MESH_SPLIT:
            if order == 1:
                _split(x, v, rest, st, fp, u0)
            else:
                _split_quadratic(x, v, rest, st, fp, u0)
        elif order == 1:
            owed = _merge(x, v, rest, st, fp, u0, v0, feed, True)
            fp[FP_OWED] += owed
            acc[ACC_OWED] += owed
        else:
            _merge_quadratic(x, v, rest, st, fp, u0, v0, feed)
    elif action == MESH_SPLIT:
        rest[0] += h
        fp[FP_PENDING] -= h
        _split(x, v, rest, st, fp, v0)
    else:
        _merge(x, v, rest, st, fp, v0, v0, 0.0, False)
        rest[0] -= h
        fp[FP_PENDING] += h
    if st[ST_NODES] != n:
        change = energy(x, v, rest, st[ST_NODES], fp, order) - e_before
        acc[ACC_RESHAPE] += change
        acc[ACC_THROUGHPUT] += abs(change)


@njit(cache=True)
def _all_finite(x, v, rest, n, order, bs, rs, acc):
    """Whether every number a step hands back is finite: the nodes' positions and velocities,
    the rest lengths, the UAV body, the winch and the energy accumulators (node 1, checked every
    internal step, can stay finite while a node further out has overflowed).
    """
    total = 0.0
    for i in range(n):
        for c in range(3):
            total += 0.0 * (x[i, c] + v[i, c])
    for e in range((n - 1) // order):
        total += 0.0 * rest[e]
    for k in range(bs.size):
        total += 0.0 * bs[k]
    for k in range(rs.size):
        total += 0.0 * rs[k]
    for k in range(acc.size):
        if k != ACC_LAST_T:
            total += 0.0 * acc[k]
    return np.isfinite(total)


@njit(cache=True)
def end_state(x, v, rest, n, fp, order, kv_on, feed, seg, force_reel, force_uav):
    """The tether's state at its ends after a step: the tension along the tether between
    consecutive nodes into seg[:n - 1] (linear: each element's; quadratic: the Gauss points'
    tension field at zeta = -1/2 and +1/2), the force on the guide way (the exit tension along
    the departing tangent) and on the UAV attachment point: the internal force on the last
    node less its lump's weight and inertia m (a - g), a the UAV end's mean acceleration over
    the last call (the lump moves with the UAV; f(l) of the UAV's Eq. 7.44). Not the end's
    acceleration at the call's end: from the samples of a UAV stepped with symplectic Euler
    (p_b = p_a + v_b T) the Hermite segment's is -2 (v_b - v_a) / T. Returns the tensions at the
    guide way and at the UAV, N (linear: the last element's tension carried over the
    half-element's weight; quadratic: the size of the force on the UAV).
    """
    mu, g = fp[FP_MU], fp[FP_G]
    t_end = 0.0
    tan, u0 = np.empty(3), np.empty(3)
    guide_tangent(x, rest, order, tan)
    for c in range(3):
        u0[c] = v[0, c] + feed * tan[c]
    f = np.zeros((n, 3))
    tens = np.zeros(n)
    if order == 1:
        element_tensions(x, v, rest, n, fp, kv_on, u0, tens)
        seg[:n - 1] = tens[:n - 1]
        t_exit = exit_tension(x, rest, tens, fp)
        e = n - 2
        d = np.sqrt((x[n - 1, 0] - x[e, 0]) ** 2 + (x[n - 1, 1] - x[e, 1]) ** 2 + (x[n - 1, 2] - x[e, 2]) ** 2)
        for c in range(3):
            f[n - 1, c] = -tens[e] * (x[n - 1, c] - x[e, c]) / d if d > 0.0 else 0.0
        t_end = tens[e] + 0.5 * mu * g * (x[n - 1, 2] - x[e, 2]) / d * rest[e] if tens[e] > 0.0 and d > 0.0 else 0.0
    else:
        tkv = np.zeros(n)
        quadratic_forces(x, v, rest, n, fp, kv_on, u0, tens, tkv, f, np.zeros((n, 4)))
        t_exit = quadratic_exit_force(f[0], lump(rest, n, order, mu, 0), fp, force_reel)
        w = 0.5 - np.sqrt(3.0) / 4.0  # zeta = -1/2 between the Gauss points -1/sqrt3 and 1/sqrt3
        for e in range((n - 1) // 2):
            ta, tb = tens[2 * e], tens[2 * e + 1]
            seg[2 * e] = max((1.0 - w) * ta + w * tb, 0.0)
            seg[2 * e + 1] = max(w * ta + (1.0 - w) * tb, 0.0)
    for c in range(3):
        force_uav[c] = f[n - 1, c]
    m_end = lump(rest, n, order, mu, n - 1)
    for c in range(3):
        force_uav[c] -= m_end * fp[FP_ACC_UAV + c]
    force_uav[2] -= m_end * g
    if order == 1:
        norm = np.sqrt(tan[0] ** 2 + tan[1] ** 2 + tan[2] ** 2)
        for c in range(3):
            force_reel[c] = t_exit * tan[c] / norm if norm > 0.0 else 0.0
    else:
        t_end = np.sqrt(force_uav[0] ** 2 + force_uav[1] ** 2 + force_uav[2] ** 2) if tens[n - 2] > 0.0 else 0.0
    return t_exit, t_end


@njit(cache=True)
def node_arc(rest, order, out):
    """Unstretched distance of each node from the guide way (m, into ``out``, 2 len(rest) + 1 for
    quadratic elements, whose middle node is halfway) for element rest lengths ``rest``.
    """
    s = 0.0
    out[0] = 0.0
    for e in range(rest.size):
        if order == 2:
            out[2 * e + 1] = s + 0.5 * rest[e]
        s += rest[e]
        out[order * (e + 1)] = s


@njit(cache=True)
def lowest_point(x, n, order, out):
    """The lowest point of the tether (m, into ``out``): the lowest node; on quadratic elements
    the lowest point of an element's parabola (Eq. 8.23) where it lies inside the element and
    below that node (the first such minimum in node order).
    """
    best = 0
    for i in range(1, n):
        if x[i, 2] < x[best, 2]:
            best = i
    for c in range(3):
        out[c] = x[best, c]
    if order == 2:
        for e in range((n - 1) // 2):
            j = 2 * e
            curve = x[j, 2] - 2.0 * x[j + 1, 2] + x[j + 2, 2]
            if curve <= 0.0:
                continue
            z = 0.5 * (x[j, 2] - x[j + 2, 2]) / curve
            if abs(z) >= 1.0:
                continue
            wa, wm, wb = 0.5 * (z * z - z), 1.0 - z * z, 0.5 * (z * z + z)
            low = wa * x[j, 2] + wm * x[j + 1, 2] + wb * x[j + 2, 2]
            if low < out[2]:
                for c in range(3):
                    out[c] = wa * x[j, c] + wm * x[j + 1, c] + wb * x[j + 2, c]


# The scalars of :func:`report`: tensions at the guide way and at the UAV (N), departure and
# arrival angles (rad), kinetic, potential and strain energy (J), the largest tension between
# nodes (N), and the deployed rest length (m, with what a merge still owes the reel element).
(RV_T_REEL, RV_T_UAV, RV_ALPHA, RV_BETA, RV_KINETIC, RV_POTENTIAL, RV_STRAIN, RV_MAX_TENSION,
 RV_REST) = range(9)
RV_SIZE = 9


@njit(cache=True)
def report(x, v, rest, n, fp, order, kv_on, feed, nodes, velocities, arc, lumps, seg, force_reel, force_uav,
           lowest, values):
    """Everything the plant reports after a step, in one call: the nodes' positions, velocities,
    unstretched arc lengths (what a merge still owes the reel element added past the guide way)
    and lumped masses into ``nodes``, ``velocities``, ``arc``, ``lumps`` (n rows); the tensions
    between nodes and the forces on both ends (:func:`end_state`); the lowest point
    (:func:`lowest_point`); the scalars into ``values`` (the ``RV_`` slots; the angles are the
    end tangents' elevations, Sec. 3.1's departure and arrival angles; the energies
    :func:`~tether_dynamics.plant.energies.tether_energies`).
    """
    mu, g, owed = fp[FP_MU], fp[FP_G], fp[FP_OWED]
    elements = (n - 1) // order
    rest_total = 0.0
    for e in range(elements):
        rest_total += rest[e]
    node_arc(rest[:elements], order, arc)
    for i in range(n):
        if i > 0:
            arc[i] += owed
        lumps[i] = lump(rest, n, order, mu, i)
        for c in range(3):
            nodes[i, c] = x[i, c]
            velocities[i, c] = v[i, c]
    t_exit, t_end = end_state(x, v, rest, n, fp, order, kv_on, feed, seg, force_reel, force_uav)
    lowest_point(x, n, order, lowest)
    e_a, e_b = np.empty(3), np.empty(3)
    for c in range(3):
        if order == 1:
            e_a[c] = x[1, c] - x[0, c]
            e_b[c] = x[n - 1, c] - x[n - 2, c]
        else:
            e_a[c] = -3.0 * x[0, c] + 4.0 * x[1, c] - x[2, c]
            e_b[c] = x[n - 3, c] - 4.0 * x[n - 2, c] + 3.0 * x[n - 1, c]
    largest = seg[0]
    for k in range(1, n - 1):
        largest = max(largest, seg[k])
    values[RV_T_REEL], values[RV_T_UAV] = t_exit, t_end
    values[RV_ALPHA] = np.arctan2(e_a[2], np.hypot(e_a[0], e_a[1]))
    values[RV_BETA] = np.arctan2(e_b[2], np.hypot(e_b[0], e_b[1]))
    values[RV_KINETIC], values[RV_POTENTIAL], values[RV_STRAIN] = tether_energies(
        nodes, velocities, lumps, seg, arc, g, fp[FP_EA])
    values[RV_MAX_TENSION] = largest
    values[RV_REST] = rest_total + owed


@njit(cache=True)
def report_finite(seg, n, force_reel, force_uav, lowest, values):
    """Whether what :func:`report` wrote is finite: the n - 1 tensions, both end forces, the lowest
    point and the scalars.
    """
    for k in range(n - 1):
        if not np.isfinite(seg[k]):
            return False
    for arr in (force_reel, force_uav, lowest, values):
        for j in range(arr.size):
            if not np.isfinite(arr[j]):
                return False
    return True
