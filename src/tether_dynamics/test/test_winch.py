"""The winch equation (Eq. 7.42) of tether_dynamics.winch against closed-form values."""

from __future__ import annotations

import math

import pytest

from tether_dynamics.plant import bodies
from tether_dynamics.winch import required_torque
from tether_dynamics.winch import spool_rate_step
from tether_dynamics.winch import wound_inertia

import numpy as np


def run(rate, torque, tension, *, radius=0.1, inertia=0.05, viscous=0.2, coulomb=0.0, static=0.0, h=1e-3, steps=1):
    for _ in range(steps):
        rate = spool_rate_step(rate, torque, tension, radius, inertia, viscous, coulomb, static, 1e-3, h)
    return rate


def test_steady_rate_is_net_torque_over_viscous_friction():
    # J w' = u + d T - c w - tau_c: w_ss = (u + d T - tau_c) / c, approached with time constant J / c
    assert run(0.0, 1.0, 20.0, coulomb=0.5, static=0.6, steps=20_000) == pytest.approx((1.0 + 2.0 - 0.5) / 0.2)
    assert run(0.0, -3.0, 10.0, coulomb=0.5, static=0.6, steps=20_000) == pytest.approx((-3.0 + 1.0 + 0.5) / 0.2)
    tau = 0.05 / 0.2
    assert run(0.0, 1.0, 0.0, steps=int(tau / 1e-3)) == pytest.approx(5.0 * (1.0 - math.exp(-1.0)), rel=2e-3)


def test_stiction_holds_below_the_static_torque_and_breaks_away_above():
    assert run(0.0, 0.3, 2.0, coulomb=0.4, static=0.55, steps=100) == 0.0   # |0.3 + 0.2| <= 0.55
    assert run(0.0, 0.4, 2.0, coulomb=0.4, static=0.55, steps=100) > 0.0    # 0.6 > 0.55


def test_coulomb_friction_stops_a_coasting_spool_instead_of_reversing_it():
    rates = [1.0]
    for _ in range(2000):
        rates.append(run(rates[-1], 0.0, 0.0, coulomb=0.4, static=0.5))
    assert rates[-1] == 0.0 and min(rates) == 0.0


def test_implicit_viscous_term_is_stable_at_a_step_far_above_the_time_constant():
    # c h / J = 100: an explicit step would flip the sign and grow; the implicit one decays to w_ss
    assert run(0.0, 1.0, 0.0, viscous=50.0, inertia=0.005, h=0.01, steps=5) == pytest.approx(1.0 / 50.0, rel=1e-6)


def test_required_torque_inverts_a_step():
    new = spool_rate_step(0.3, 1.2, 15.0, 0.1, 0.05, 0.2, 0.0, 0.0, 0.0, 0.01)
    assert required_torque(0.3, new, 15.0, 0.1, 0.05, 0.2, 0.01) == pytest.approx(1.2)


def test_plant_reel_step_is_the_same_equation():
    rp = np.zeros(7)
    rp[bodies.RP_RADIUS], rp[bodies.RP_INERTIA], rp[bodies.RP_FRICTION] = 0.1, 0.05, 0.2
    rp[bodies.RP_MU], rp[bodies.RP_TOTAL], rp[bodies.RP_MIN], rp[bodies.RP_MAX] = 0.042, 100.0, 1.0, 90.0
    rs = np.zeros(6)
    rs[bodies.RS_LENGTH], rs[bodies.RS_RATE] = 10.0, 0.3
    bodies.reel_step(rs, rp, True, 1.2, 15.0, 0.01)
    inertia = 0.05 + wound_inertia(0.042, 90.0, 0.1)
    assert rs[bodies.RS_RATE] == spool_rate_step(0.3, 1.2, 15.0, 0.1, inertia, 0.2, 0.0, 0.0, 0.0, 0.01)
