"""The two bodies at the tether's ends: the winch (Eq. 7.26 / 7.42) and the UAV (Eq. 7.44-7.45).

Compiled (numba) so the finite-element stepper calls them every internal step; the
quasi-static plant calls the same functions from Python.

Winch. The winch equation of Eq. 7.26 / 7.42 is :mod:`tether_dynamics.winch` (the same
functions the smart reel steps), compiled here: with the payout rate Ldot = d omega (d the
spool radius, omega + paying out), (mu s_d d^2 + J_d) omegadot = u + d T_A - c omega: the
wound tether (length s_d, the drum's share of the conserved tether mass) adds to the drum's
inertia, the tether's tension at the guide way T_A pulls the spool towards payout, u is the
motor torque (+ pays out) and c viscous friction (taken implicitly). The plant's drum has no
Coulomb friction or stiction (the smart reel models its own drive). Neglected, and named: the
torque of the partial wrap's weight (mu g d sin((s_d - b)/d), at most mu g d^2, 1e-4 N m
for the defaults), the guide-way segment b, and the reaction of the winch on the boat
(Eq. 7.40-7.41: the boat's motion is prescribed). A prescribed spool rate skips the
equation and reports the torque it required.

UAV. A rigid body about its centre of mass (the form of Eq. 7.44-7.45 with the reference
point moved from the attachment point to the centre of mass): m a = F R e3 + m g + f,
Pi Omegadot = tau + rho x (R^T f) - Omega x Pi Omega, with f the tether's force at the
attachment point rho (body frame). Semi-implicit Euler; the attitude is advanced on the
unit quaternions by the exact exponential of the body rate.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from tether_dynamics import winch

_spool_rate_step = njit(cache=True)(winch.spool_rate_step)
_required_torque = njit(cache=True)(winch.required_torque)
_wound_inertia = njit(cache=True)(winch.wound_inertia)

# Reel parameter vector rp.
RP_RADIUS, RP_INERTIA, RP_FRICTION, RP_MU, RP_TOTAL, RP_MIN, RP_MAX = range(7)
# Reel state vector rs: spool angle, spool rate, deployed length, motor work, last applied torque, at a stop.
RS_ANGLE, RS_RATE, RS_LENGTH, RS_WORK, RS_TORQUE, RS_STOP = range(6)


@njit(cache=True)
def reel_step(rs, rp, torque_input, command, tension, dt):
    """Advance the winch by dt under the tether tension at the guide way; returns the change
    of deployed length over the step divided by dt (the payout rate, cut at an end stop).

    ``torque_input``: the command is the motor torque (N m); else it is the spool rate (rad/s).
    The deployed length stops at [min, max] (the spool then stands still).
    """
    d = rp[RP_RADIUS]
    j_eff = rp[RP_INERTIA] + _wound_inertia(rp[RP_MU], rp[RP_TOTAL] - rs[RS_LENGTH], d)
    old = rs[RS_RATE]
    if torque_input:
        rate = _spool_rate_step(old, command, tension, d, j_eff, rp[RP_FRICTION], 0.0, 0.0, 0.0, dt)
        torque = command
    else:
        rate = command
        torque = _required_torque(old, rate, tension, d, j_eff, rp[RP_FRICTION], dt)
    old_length = rs[RS_LENGTH]
    length = old_length + dt * d * rate
    stop = 0.0
    if length >= rp[RP_MAX] and rate >= 0.0:
        length, rate, stop = rp[RP_MAX], 0.0, 1.0
    elif length <= rp[RP_MIN] and rate <= 0.0:
        length, rate, stop = rp[RP_MIN], 0.0, 1.0
    rs[RS_WORK] += dt * torque * rate
    rs[RS_ANGLE] += dt * rate
    rs[RS_RATE] = rate
    rs[RS_LENGTH] = length
    rs[RS_TORQUE] = torque
    rs[RS_STOP] = stop
    return (length - old_length) / dt


@njit(cache=True, inline='always')
def _rotated(x, y, z, w, v0, v1, v2):
    """R(q) v for the unit quaternion q = (x, y, z, w), as a tuple (no array: called every internal step)."""
    tx = 2.0 * (y * v2 - z * v1)
    ty = 2.0 * (z * v0 - x * v2)
    tz = 2.0 * (x * v1 - y * v0)
    return v0 + w * tx + (y * tz - z * ty), v1 + w * ty + (z * tx - x * tz), v2 + w * tz + (x * ty - y * tx)


@njit(cache=True)
def quat_rotate(q, vec, out):
    """out = R(q) vec for a unit quaternion q = (x, y, z, w)."""
    out[0], out[1], out[2] = _rotated(q[0], q[1], q[2], q[3], vec[0], vec[1], vec[2])


@njit(cache=True)
def quat_rotate_inverse(q, vec, out):
    """out = R(q)^T vec."""
    out[0], out[1], out[2] = _rotated(-q[0], -q[1], -q[2], q[3], vec[0], vec[1], vec[2])


@njit(cache=True, inline='always')
def _times(m, v0, v1, v2):
    """The (3, 3) matrix m times (v0, v1, v2), as a tuple."""
    return (m[0, 0] * v0 + m[0, 1] * v1 + m[0, 2] * v2, m[1, 0] * v0 + m[1, 1] * v1 + m[1, 2] * v2,
            m[2, 0] * v0 + m[2, 1] * v1 + m[2, 2] * v2)


# Body state bs: position (3), velocity (3), quaternion x y z w (4), body rate (3), acceleration (3).
BS_POS, BS_VEL, BS_QUAT, BS_OMEGA, BS_ACC = 0, 3, 6, 10, 13
BS_SIZE = 16


@njit(cache=True)
def body_attach(bs, rho, pos, vel):
    """World position and velocity of the attachment point rho (body frame)."""
    x, y, z, w = bs[BS_QUAT], bs[BS_QUAT + 1], bs[BS_QUAT + 2], bs[BS_QUAT + 3]
    r0, r1, r2 = _rotated(x, y, z, w, rho[0], rho[1], rho[2])
    w0, w1, w2 = _rotated(x, y, z, w, bs[BS_OMEGA], bs[BS_OMEGA + 1], bs[BS_OMEGA + 2])
    pos[0] = bs[0] + r0
    pos[1] = bs[1] + r1
    pos[2] = bs[2] + r2
    vel[0] = bs[3] + w1 * r2 - w2 * r1
    vel[1] = bs[4] + w2 * r0 - w0 * r2
    vel[2] = bs[5] + w0 * r1 - w1 * r0


@njit(cache=True)
def body_step(bs, mass, inertia, inertia_inv, rho, thrust, torque, force, gravity, dt):
    """Advance the UAV by dt under thrust (N, body +z), body torque (N m), gravity (m/s^2,
    along -z) and the tether force ``force`` (N, world) at the attachment point. Scalar code,
    no arrays made: it runs every internal step of the tether plant and of the built-in UAV.
    """
    x, y, z, w = bs[BS_QUAT], bs[BS_QUAT + 1], bs[BS_QUAT + 2], bs[BS_QUAT + 3]
    up = _rotated(x, y, z, w, 0.0, 0.0, 1.0)
    for c in range(3):
        acc = (thrust * up[c] + force[c]) / mass
        if c == 2:
            acc -= gravity
        bs[BS_ACC + c] = acc
        bs[BS_VEL + c] += dt * acc
        bs[BS_POS + c] += dt * bs[BS_VEL + c]
    f0, f1, f2 = _rotated(-x, -y, -z, w, force[0], force[1], force[2])
    o0, o1, o2 = bs[BS_OMEGA], bs[BS_OMEGA + 1], bs[BS_OMEGA + 2]
    a0, a1, a2 = _times(inertia, o0, o1, o2)
    rhs0 = torque[0] + rho[1] * f2 - rho[2] * f1 - (o1 * a2 - o2 * a1)
    rhs1 = torque[1] + rho[2] * f0 - rho[0] * f2 - (o2 * a0 - o0 * a2)
    rhs2 = torque[2] + rho[0] * f1 - rho[1] * f0 - (o0 * a1 - o1 * a0)
    d0, d1, d2 = _times(inertia_inv, rhs0, rhs1, rhs2)
    o0, o1, o2 = o0 + dt * d0, o1 + dt * d1, o2 + dt * d2
    bs[BS_OMEGA], bs[BS_OMEGA + 1], bs[BS_OMEGA + 2] = o0, o1, o2
    # q <- q (x) exp(dt om / 2), body rate: right multiplication.
    theta = np.sqrt(o0 ** 2 + o1 ** 2 + o2 ** 2) * dt
    if theta > 0.0:
        s = np.sin(0.5 * theta) / (theta / dt)
        dx, dy, dz, dw = s * o0, s * o1, s * o2, np.cos(0.5 * theta)
        nx = w * dx + x * dw + y * dz - z * dy
        ny = w * dy - x * dz + y * dw + z * dx
        nz = w * dz + x * dy - y * dx + z * dw
        nw = w * dw - x * dx - y * dy - z * dz
        norm = np.sqrt(nx * nx + ny * ny + nz * nz + nw * nw)
        bs[BS_QUAT], bs[BS_QUAT + 1], bs[BS_QUAT + 2], bs[BS_QUAT + 3] = nx / norm, ny / norm, nz / norm, nw / norm
