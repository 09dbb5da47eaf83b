"""The built-in UAV: take off, hold a setpoint against the tether's pull, land and disarm."""

from __future__ import annotations

import numpy as np
import pytest

from uav_bridge.builtin_uav import BuiltinUav
from uav_bridge.builtin_uav import BuiltinUavConfig


def _run(uav, t0, t1, force, rate=100.0):
    state = None
    for k in range(int(round((t1 - t0) * rate)) + 1):
        state = uav.step(t0 + k / rate, force)
    return state


def test_takeoff_hold_and_land_like_arducopter_in_guided():
    uav = BuiltinUav(BuiltinUavConfig(start=(1.0, 2.0, 0.5)))
    pull = np.array([-2.0, 0.0, -3.0])
    state = _run(uav, 0.0, 1.0, pull)
    np.testing.assert_allclose(state.position, [1.0, 2.0, 0.5])   # at rest while disarmed, whatever pulls
    assert not uav.takeoff(5.0)[0]                                # refused before arming
    assert uav.set_mode('GUIDED')[0] and uav.arm(True)[0]
    assert uav.takeoff(5.0) == (True, 'takeoff accepted')
    state = _run(uav, 1.0, 16.0, pull)
    assert state.position == pytest.approx([1.0, 2.0, 5.5], abs=0.05)
    assert uav.setpoint([3.0, 2.5, 5.0])
    state = _run(uav, 16.0, 40.0, pull)
    np.testing.assert_allclose(state.position, [3.0, 2.5, 5.0], atol=0.05)
    assert not uav.arm(False)[0]                                  # no disarming in flight
    assert uav.land()[0]
    state = _run(uav, 40.0, 60.0, pull)
    assert not state.armed and state.mode == 'LAND'
    np.testing.assert_allclose(state.position, [3.0, 2.5, 0.5], atol=0.05)   # rests where it touched down
    assert state.position[2] == pytest.approx(0.5)
    assert not uav.set_mode('LOITER')[0]


def test_land_descends_at_the_land_speed():
    uav = BuiltinUav(BuiltinUavConfig())
    uav.arm(True)
    uav.takeoff(10.0)
    _run(uav, 0.0, 20.0, np.zeros(3))
    uav.land()
    heights = [_run(uav, 20.0 + k, 21.0 + k, np.zeros(3)).position[2] for k in range(8)]
    rates = -np.diff(heights[2:])
    np.testing.assert_allclose(rates, 0.5, atol=0.02)


def test_a_start_height_starts_hovering_armed_in_guided():
    uav = BuiltinUav(BuiltinUavConfig(start=(15.0, 0.0, 0.0), start_height=28.0))
    pull = np.array([-4.0, 0.0, -12.0])                           # a 30 m tether's weight and pull
    state = _run(uav, 0.0, 0.0, pull)
    assert state.armed and state.mode == 'GUIDED'
    np.testing.assert_allclose(state.position, [15.0, 0.0, 28.0])
    state = _run(uav, 0.0, 20.0, pull)
    np.testing.assert_allclose(state.position, [15.0, 0.0, 28.0], atol=0.02)   # holds where it started
    assert uav.takeoff(2.0)[0]                                    # the mission's take-off climbs from there
    state = _run(uav, 20.0, 40.0, pull)
    np.testing.assert_allclose(state.position, [15.0, 0.0, 30.0], atol=0.05)
