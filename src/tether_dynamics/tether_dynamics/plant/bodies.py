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


@njit(cache=True)
def quat_rotate(q, vec, out):
    """out = R(q) vec for a unit quaternion q = (x, y, z, w)."""
    x, y, z, w = q[0], q[1], q[2], q[3]
    tx = 2.0 * (y * vec[2] - z * vec[1])
    ty = 2.0 * (z * vec[0] - x * vec[2])
    tz = 2.0 * (x * vec[1] - y * vec[0])
    out[0] = vec[0] + w * tx + (y * tz - z * ty)
    out[1] = vec[1] + w * ty + (z * tx - x * tz)
    out[2] = vec[2] + w * tz + (x * ty - y * tx)


@njit(cache=True)
def quat_rotate_inverse(q, vec, out):
    """out = R(q)^T vec."""
    qc = np.array([-q[0], -q[1], -q[2], q[3]])
    quat_rotate(qc, vec, out)


# Body state bs: position (3), velocity (3), quaternion x y z w (4), body rate (3), acceleration (3).
BS_POS, BS_VEL, BS_QUAT, BS_OMEGA, BS_ACC = 0, 3, 6, 10, 13
BS_SIZE = 16


@njit(cache=True)
def body_attach(bs, rho, pos, vel):
    """World position and velocity of the attachment point rho (body frame)."""
    q = bs[BS_QUAT:BS_QUAT + 4]
    r = np.empty(3)
    quat_rotate(q, rho, r)
    om = bs[BS_OMEGA:BS_OMEGA + 3]
    w = np.empty(3)
    quat_rotate(q, om, w)
    pos[0] = bs[0] + r[0]
    pos[1] = bs[1] + r[1]
    pos[2] = bs[2] + r[2]
    vel[0] = bs[3] + w[1] * r[2] - w[2] * r[1]
    vel[1] = bs[4] + w[2] * r[0] - w[0] * r[2]
    vel[2] = bs[5] + w[0] * r[1] - w[1] * r[0]


@njit(cache=True)
def body_step(bs, mass, inertia, inertia_inv, rho, thrust, torque, force, gravity, dt):
    """Advance the UAV by dt under thrust (N, body +z), body torque (N m), gravity (m/s^2,
    along -z) and the tether force ``force`` (N, world) at the attachment point.
    """
    q = bs[BS_QUAT:BS_QUAT + 4].copy()
    up = np.array([0.0, 0.0, 1.0])
    thrust_w = np.empty(3)
    quat_rotate(q, up, thrust_w)
    for c in range(3):
        acc = (thrust * thrust_w[c] + force[c]) / mass
        if c == 2:
            acc -= gravity
        bs[BS_ACC + c] = acc
        bs[BS_VEL + c] += dt * acc
        bs[BS_POS + c] += dt * bs[BS_VEL + c]
    f_body = np.empty(3)
    quat_rotate_inverse(q, force, f_body)
    om = bs[BS_OMEGA:BS_OMEGA + 3].copy()
    ang = inertia @ om
    rhs = np.empty(3)
    rhs[0] = torque[0] + rho[1] * f_body[2] - rho[2] * f_body[1] - (om[1] * ang[2] - om[2] * ang[1])
    rhs[1] = torque[1] + rho[2] * f_body[0] - rho[0] * f_body[2] - (om[2] * ang[0] - om[0] * ang[2])
    rhs[2] = torque[2] + rho[0] * f_body[1] - rho[1] * f_body[0] - (om[0] * ang[1] - om[1] * ang[0])
    om_dot = inertia_inv @ rhs
    for c in range(3):
        om[c] += dt * om_dot[c]
        bs[BS_OMEGA + c] = om[c]
    # q <- q (x) exp(dt om / 2), body rate: right multiplication.
    theta = np.sqrt(om[0] ** 2 + om[1] ** 2 + om[2] ** 2) * dt
    if theta > 0.0:
        s = np.sin(0.5 * theta) / (theta / dt)
        dx, dy, dz, dw = s * om[0], s * om[1], s * om[2], np.cos(0.5 * theta)
        x, y, z, w = q[0], q[1], q[2], q[3]
        nq = np.array([w * dx + x * dw + y * dz - z * dy,
                       w * dy - x * dz + y * dw + z * dx,
                       w * dz + x * dy - y * dx + z * dw,
                       w * dw - x * dx - y * dy - z * dz])
        nq /= np.sqrt(np.sum(nq * nq))
        bs[BS_QUAT:BS_QUAT + 4] = nq
