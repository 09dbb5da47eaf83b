"""The reel core in closed loop against the quasi-static catenary (the tuning's design simulation)."""

from __future__ import annotations

import numpy as np
import pytest

from smart_reel.reel import ReelInputs
from smart_reel.reel import build_core
from smart_reel.tuning import default_parameters
from smart_reel.tuning import heave_profile
from smart_reel.tuning import simulate


def test_catenary_controller_follows_the_reference_on_the_jonswap_profile():
    params = default_parameters()
    sim = simulate(params, *heave_profile('jonswap', 30.0, 100.0, seed=2))
    keep = sim['t'] >= 5.0
    err = sim['deployed'][keep] - sim['reference'][keep]
    assert np.sqrt(np.mean(err**2)) <= 0.015
    assert np.ptp(sim['reference']) > 1.0  # the profile does move the reference


def test_locked_reel_never_turns():
    core = build_core(dict(default_parameters(), controller='locked'), 8.0)
    for k in range(100):
        out = core.step(k * 0.01, ReelInputs(3.22, 7.0, 0.5, 20.0, 0.5))
    assert out.deployed_length == 8.0 and out.drive == 'brake' and out.mode == 'locked'


def test_taut_controller_reels_in_until_the_pull_balances_its_torque():
    params = default_parameters()
    core = build_core(dict(params, controller='taut'), 8.0)
    radius = core.winch.spool.radius(8.0)
    weak = 0.5 * params['taut_torque'] / radius
    for k in range(50):
        out = core.step(k * 0.01, ReelInputs(tension=weak))
    assert out.payout_rate < 0.0 and out.mode == 'taut' and out.drive == 'current'
    strong = (params['taut_torque'] + 2.0 * params['friction_static']) / radius
    for k in range(50, 150):
        out = core.step(k * 0.01, ReelInputs(tension=strong))
    assert out.payout_rate > 0.0


def test_catenary_controller_waits_for_the_relative_position():
    core = build_core(default_parameters(), 8.0)
    out = core.step(0.0, ReelInputs(tension=1.0))
    assert out.drive == 'brake' and out.control is None


def test_commanded_payout_pulls_the_plant_length_onto_the_reel_length():
    core = build_core(dict(default_parameters(), controller='locked', sync_gain=10.0), 8.0)
    first = core.step(0.0, ReelInputs())
    assert first.command_payout == 0.0
    # the plant reports 7.9 m at t = 0.01 while the reel's drum says 8.0 m: pay out 10/s x 0.1 m
    out = core.step(0.01, ReelInputs(plant_length=7.9, plant_time=0.01))
    assert out.payout_rate == 0.0
    assert out.command_payout == pytest.approx(1.0)
    # a stamp the reel has no length for (before its start) adds nothing
    assert core.step(0.02, ReelInputs(plant_length=7.9, plant_time=-5.0)).command_payout == 0.0


def test_corrections_in_flight_are_not_repeated():
    core = build_core(dict(default_parameters(), controller='locked', sync_gain=10.0), 8.0)
    core.step(0.0, ReelInputs())
    core.step(0.01, ReelInputs())
    # the plant is 0.1 m short at t = 0.01; two ticks see that same stamp
    first = core.step(0.02, ReelInputs(plant_length=7.9, plant_time=0.01))
    second = core.step(0.03, ReelInputs(plant_length=7.9, plant_time=0.01))
    assert first.command_payout == pytest.approx(1.0)
    assert second.command_payout == pytest.approx(10.0 * (0.1 - 1.0 * 0.01))
