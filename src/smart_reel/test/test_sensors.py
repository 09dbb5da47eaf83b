"""Guide-arm dead-band on a constructed reversal; tension from motor current."""

from __future__ import annotations

import math

import pytest

from smart_reel.sensors import GuideArm
from smart_reel.sensors import tension_from_current

DEADBAND = math.radians(20.0)


def test_reading_jumps_by_the_deadband_when_the_reel_reverses():
    arm = GuideArm(DEADBAND, bits=12)
    gamma = math.radians(35.0)
    out = [arm.read(gamma, 0.3) for _ in range(5)]
    back = [arm.read(gamma, -0.3) for _ in range(5)]
    assert out[-1] - back[0] == pytest.approx(DEADBAND, abs=arm.resolution)
    assert out[-1] == pytest.approx(gamma + DEADBAND / 2, abs=arm.resolution / 2)
    assert back[-1] == pytest.approx(gamma - DEADBAND / 2, abs=arm.resolution / 2)


def test_reading_keeps_its_side_through_a_stop_and_slow_creep():
    arm = GuideArm(DEADBAND, switch_speed=0.005)
    gamma = math.radians(30.0)
    paying = arm.read(gamma, 0.2)
    assert arm.read(gamma, 0.0) == paying
    assert arm.read(gamma, -0.004) == paying
    assert arm.read(gamma, -0.006) == pytest.approx(paying - DEADBAND, abs=arm.resolution)


def test_reading_follows_the_tether_between_reversals_on_the_encoder_grid():
    arm = GuideArm(DEADBAND, bits=12)
    q = 2 * math.pi / 4096
    for deg in (10.0, 10.01, 10.05, 40.0):
        reading = arm.read(math.radians(deg), 0.1)
        assert reading / q == pytest.approx(round(reading / q), abs=1e-9)
        assert abs(reading - math.radians(deg) - DEADBAND / 2) <= q / 2 + 1e-12


def test_tension_from_current_balances_torque_friction_and_the_spools_acceleration():
    # at rest: T r = -N K i
    assert tension_from_current(-0.5, 0.0, 0.0, 0.01, 0.08, 4.0, 0.3, 0.02, 0.25) == pytest.approx(25.0)
    # paying out at 2 rad/s: T r = -N K i + b w + tau_c
    assert tension_from_current(-0.5, 2.0, 0.0, 0.01, 0.08, 4.0, 0.3, 0.02, 0.25) == \
        pytest.approx((2.0 + 0.04 + 0.25) / 0.08)
    # speeding up the payout by 0.1 rad/s in 10 ms takes J dw/dt = 3 N m of the pull
    assert tension_from_current(-0.5, 2.0, 0.1, 0.01, 0.08, 4.0, 0.3, 0.02, 0.25) == \
        pytest.approx((2.0 + 0.04 + 0.25 + 3.0) / 0.08)
