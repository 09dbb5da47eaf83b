"""Motor and winch: steady-state speed, stall torque, current limit and stiction against closed forms."""

from __future__ import annotations

import math

import pytest

from smart_reel.motor import MotorParameters
from smart_reel.motor import stall_torque
from smart_reel.motor import steady_state_rate
from smart_reel.spool import SpoolGeometry
from smart_reel.winch import BRAKE
from smart_reel.winch import CURRENT
from smart_reel.winch import VOLTAGE
from smart_reel.winch import Friction
from smart_reel.winch import Winch

MOTOR = MotorParameters()
SPOOL = SpoolGeometry(0.05, 0.12, 0.0045, 100.0, 0.042)
FRICTION = Friction(viscous=0.02, coulomb=0.25, static=0.35)


def settle(winch: Winch, drive: str, command: float, tension: float, seconds: float = 1.0) -> None:
    for _ in range(round(seconds / 0.01)):
        winch.step(0.01, drive, command, tension)


@pytest.mark.parametrize('voltage', [6.0, 24.0, -24.0])
def test_steady_state_speed_under_voltage_matches_closed_form(voltage):
    winch = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    settle(winch, VOLTAGE, voltage, 0.0)
    expected = steady_state_rate(MOTOR, voltage, 0.0, FRICTION.viscous, FRICTION.coulomb)
    # (N K V/R - tau_c) / ((N K)^2/R + b), by hand for 24 V: (4*24/1.5 - 0.25)/(16/1.5 + 0.02)
    if voltage == 24.0:
        assert expected == pytest.approx((4.0 * 24.0 / 1.5 - 0.25) / (16.0 / 1.5 + 0.02), rel=1e-12)
    assert winch.state.spool_rate == pytest.approx(expected, rel=1e-6)
    assert winch.state.current == pytest.approx((voltage - MOTOR.shaft_constant * expected) / MOTOR.resistance,
                                                rel=1e-6)


def test_steady_state_speed_against_tether_pull():
    tension = 30.0
    winch = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    settle(winch, VOLTAGE, -24.0, tension, 0.5)
    load = -tension * SPOOL.radius(winch.deployed)  # the pull pays out: a negative opposing torque
    expected = steady_state_rate(MOTOR, -24.0, load, FRICTION.viscous, FRICTION.coulomb)
    assert winch.state.spool_rate == pytest.approx(expected, rel=1e-3)


def test_stall_torque_balances_the_pull_at_zero_speed():
    frictionless = Friction(0.0, 0.0, 0.0)
    voltage = -6.0  # 4 A < 12 A limit: stall torque N K V/R = -16 N m
    assert stall_torque(MOTOR, voltage) == pytest.approx(-16.0)
    radius = SPOOL.radius(50.0)
    for factor, sign in ((0.98, -1.0), (1.02, 1.0)):
        winch = Winch(MOTOR, SPOOL, frictionless, 0.004, 50.0)
        tension = -factor * stall_torque(MOTOR, voltage) / radius
        settle(winch, VOLTAGE, voltage, tension, 0.5)
        assert math.copysign(1.0, winch.state.spool_rate) == sign
        expected = steady_state_rate(MOTOR, voltage, -tension * radius)
        assert winch.state.spool_rate == pytest.approx(expected, rel=1e-3)


def test_stall_torque_is_current_limited():
    assert stall_torque(MOTOR, 48.0) == pytest.approx(MOTOR.shaft_constant * MOTOR.current_limit)
    winch = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    # held at stall by a pull equal to the limited torque: 48 V / 1.5 ohm = 32 A is clipped to 12 A
    tension = MOTOR.shaft_constant * MOTOR.current_limit / SPOOL.radius(50.0)
    settle(winch, VOLTAGE, -48.0, tension, 0.2)
    assert winch.state.current == pytest.approx(-MOTOR.current_limit)
    assert winch.state.current_limited
    assert abs(winch.state.spool_rate) < 1e-3


def test_stiction_holds_below_and_breaks_away_above_the_static_friction():
    radius = SPOOL.radius(50.0)
    below = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    settle(below, BRAKE, 0.0, 0.99 * FRICTION.static / radius, 0.2)
    settle(below, CURRENT, 0.0, 0.99 * FRICTION.static / radius, 0.5)
    assert below.state.spool_rate == 0.0 and below.state.stuck
    assert below.deployed == 50.0
    above = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    settle(above, CURRENT, 0.0, 1.01 * FRICTION.static / radius, 0.5)
    assert above.state.spool_rate > 0.0 and above.deployed > 50.0


def test_current_mode_holds_the_commanded_torque():
    winch = Winch(MOTOR, SPOOL, FRICTION, 0.004, 50.0)
    settle(winch, CURRENT, -1.5 / MOTOR.shaft_constant, 0.0, 0.3)
    assert winch.state.current == pytest.approx(-1.5 / MOTOR.shaft_constant)
    assert winch.state.spool_rate < 0.0


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match='resistance'):
        MotorParameters(resistance=0.0)
    with pytest.raises(ValueError, match='static'):
        Friction(0.0, 0.5, 0.2)
    with pytest.raises(ValueError, match='initial deployed length'):
        Winch(MOTOR, SPOOL, FRICTION, 0.004, 150.0)
