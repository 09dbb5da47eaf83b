"""The tether's material and air laws, compiled once for both finite-element engines.

The Chapter 9 pendulum engine (:mod:`tether_dynamics.fem.kernels`) and the moving-reel plant
(:mod:`tether_dynamics.plant.fem_kernels`) differ in their state and time stepping; what a
piece of tether does under strain and in air is the same in both and lives here:

* :func:`segment_strain`: the strain and strain rate of a material segment (Eq. 8.8's
  stretch |r'|; a linear element, or a quadratic element's Gauss point);
* :func:`kelvin_voigt`: the axial force EA eps + c deps/dt, tension-only (Sec. 9.1.2:
  compression is clamped to zero force);
* :func:`wind_at`: a uniform or power-law-sheared wind;
* :func:`drag_per_length` and :func:`add_element_drag`: air drag F_D = 1/2 rho v^2 C_D A
  (Sec. 9.2.2) split into a normal part (projected area d) and a tangential part (skin,
  perimeter pi d), integrated over an element with the 2-point Gauss rule of Appendix D.3;
* :data:`GAUSS` and the status codes both engines report.
"""

from __future__ import annotations

import numpy as np
from numba import njit

# The 2-point Gauss points zeta = -+1/sqrt3 on an element's [-1, 1] (Appendix D.3).
GAUSS = np.array([-1.0 / np.sqrt(3.0), 1.0 / np.sqrt(3.0)])

# What a step reports: fine; a node or force not finite; an element past the strain limit;
# the reel's mesh out of nodes; the deployed tether shorter than the reel can hold.
STATUS_OK, STATUS_NONFINITE, STATUS_STRAIN, STATUS_FULL, STATUS_SHORT = range(5)

AIR_FIELDS = ('half_rho_d', 'cd_normal', 'cd_tangential', 'wind_u', 'wind_v', 'wind_w', 'wind_alpha', 'wind_z_ref',
              'wind_z_ground')
"""The air block each engine keeps in its float parameters (:func:`air_block`, read by
:func:`add_element_drag`): 1/2 rho d (kg/m^2), C_Dn, C_Dt, the wind U (3, m/s, world), and its
shear exponent alpha, reference height (m) and ground height (m) (:func:`wind_at`)."""
(AIR_HALF_RHO_D, AIR_CD_NORMAL, AIR_CD_TANGENTIAL, AIR_WIND, AIR_WIND_ALPHA, AIR_WIND_Z_REF,
 AIR_WIND_Z_GROUND) = (AIR_FIELDS.index(name) for name in ('half_rho_d', 'cd_normal', 'cd_tangential', 'wind_u',
                                                            'wind_alpha', 'wind_z_ref', 'wind_z_ground'))


def air_block(air_density: float, diameter: float, cd_normal: float, cd_tangential: float,
              wind: tuple[float, float, float] = (0.0, 0.0, 0.0), alpha: float = 0.0, z_ref: float = 1.0,
              z_ground: float = 0.0) -> np.ndarray:
    """The :data:`AIR_FIELDS` block: drag of a tether of ``diameter`` (m) in air of
    ``air_density`` (kg/m^3) with a wind ``wind`` (m/s, world; zero for none) sheared by ``alpha``.
    """
    return np.array([0.5 * air_density * diameter, cd_normal, cd_tangential, *wind, alpha, z_ref, z_ground], float)


@njit(cache=True, inline='always')
def segment_strain(d0, d1, d2, w0, w1, w2, inv_l0):
    """Length |d|, strain |d| / l0 - 1 and strain rate d . w / (|d| l0) of a segment d of rest
    length l0 = 1 / inv_l0 whose ends separate at w (Eq. 8.8). With inv_l0 = 1, d is the
    tangent dr/ds, |d| the stretch and w its rate.
    """
    length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    return length, length * inv_l0 - 1.0, (d0 * w0 + d1 * w1 + d2 * w2) * inv_l0 / length


@njit(cache=True, inline='always')
def kelvin_voigt(eps, eps_rate, ea, c_kv, tension_only):
    """Axial force T = EA eps + c deps/dt and its damping part (N). Tension-only (Sec. 9.1.2):
    a slack segment (eps <= 0) carries nothing, and damping never makes the force compressive
    (the damping part is then what cancels the elastic one).
    """
    if eps <= 0.0 and tension_only:
        return 0.0, 0.0
    damping = c_kv * eps_rate
    t = ea * eps + damping
    if t < 0.0 and tension_only:
        return 0.0, damping - t
    return t, damping


@njit(cache=True, inline='always')
def wind_at(z, u0, u1, u2, alpha, z_ref, z_ground):
    """Wind velocity at height z: U ((z - z_ground) / z_ref)^alpha above z_ground, zero below;
    uniform U everywhere when alpha = 0.
    """
    if alpha == 0.0:
        return u0, u1, u2
    dz = z - z_ground
    if dz <= 0.0:
        return 0.0, 0.0, 0.0
    s = (dz / z_ref) ** alpha
    return u0 * s, u1 * s, u2 * s


@njit(cache=True, inline='always')
def drag_per_length(u0, u1, u2, t0, t1, t2, half_rho_d, cd_normal, cd_tangential):
    """Drag per unit rest length (N/m) on tether with tangent t = dr/ds (|t| the stretch) in air
    moving at u relative to it: 1/2 rho d |t| (C_Dn |u_n| u_n + pi C_Dt |u_t| u_t).
    """
    stretch = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    if stretch == 0.0:
        return 0.0, 0.0, 0.0
    e0, e1, e2 = t0 / stretch, t1 / stretch, t2 / stretch
    ut = u0 * e0 + u1 * e1 + u2 * e2
    un0, un1, un2 = u0 - ut * e0, u1 - ut * e1, u2 - ut * e2
    k_n = half_rho_d * stretch * cd_normal * np.sqrt(un0 * un0 + un1 * un1 + un2 * un2)
    k_t = half_rho_d * stretch * np.pi * cd_tangential * abs(ut)
    return k_n * un0 + k_t * ut * e0, k_n * un1 + k_t * ut * e1, k_n * un2 + k_t * ut * e2


@njit(cache=True, inline='always')
def quadratic_shape(z):
    """Shape functions S1, S2, S3 of a quadratic element at zeta = z in [-1, 1] (Eq. D.5)."""
    return (z * z - z) / 2.0, 1.0 - z * z, (z * z + z) / 2.0


@njit(cache=True, inline='always')
def quadratic_slope(z):
    """dS/dzeta of :func:`quadratic_shape` at zeta = z; times 2 / l0 they give dr/ds (Eq. 8.26)."""
    return z - 0.5, -2.0 * z, z + 0.5


@njit(cache=True, inline='always')
def gauss_shape(order, g, k, l0):
    """Shape function k of a linear (order 1) or quadratic (order 2) element of rest length l0
    at Gauss point g, and its slope d/ds.
    """
    z = GAUSS[g]
    if order == 1:
        if k == 0:
            return 0.5 - 0.5 * z, -1.0 / l0
        return 0.5 + 0.5 * z, 1.0 / l0
    return quadratic_shape(z)[k], 2.0 * quadratic_slope(z)[k] / l0


@njit(cache=True, _nrt=False)
def add_element_drag(x, v, first, order, l0, fp, air, f):
    """Add the drag on the element of nodes first .. first + order (rest length l0) to f, at its
    two Gauss points, each node by its shape function (Appendix D.3 quadrature). The air block
    (:data:`AIR_FIELDS`) is fp[air:air + len(AIR_FIELDS)].
    """
    for g in range(2):
        r0 = r1 = r2 = 0.0
        u0 = u1 = u2 = 0.0
        t0 = t1 = t2 = 0.0
        for k in range(order + 1):
            sh, sl = gauss_shape(order, g, k, l0)
            r0 += sh * x[first + k, 0]
            r1 += sh * x[first + k, 1]
            r2 += sh * x[first + k, 2]
            u0 -= sh * v[first + k, 0]
            u1 -= sh * v[first + k, 1]
            u2 -= sh * v[first + k, 2]
            t0 += sl * x[first + k, 0]
            t1 += sl * x[first + k, 1]
            t2 += sl * x[first + k, 2]
        w0, w1, w2 = wind_at(r2, fp[air + AIR_WIND], fp[air + AIR_WIND + 1], fp[air + AIR_WIND + 2],
                             fp[air + AIR_WIND_ALPHA], fp[air + AIR_WIND_Z_REF], fp[air + AIR_WIND_Z_GROUND])
        fx, fy, fz = drag_per_length(u0 + w0, u1 + w1, u2 + w2, t0, t1, t2, fp[air + AIR_HALF_RHO_D],
                                     fp[air + AIR_CD_NORMAL], fp[air + AIR_CD_TANGENTIAL])
        for k in range(order + 1):
            wk = 0.5 * l0 * gauss_shape(order, g, k, l0)[0]
            f[first + k, 0] += wk * fx
            f[first + k, 1] += wk * fy
            f[first + k, 2] += wk * fz
