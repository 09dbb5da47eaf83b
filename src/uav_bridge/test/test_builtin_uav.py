"""The built-in UAV: take off, hold a setpoint against the tether's pull, land and disarm."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from uav_bridge.builtin.uav import BuiltinUav
from uav_bridge.builtin.uav import BuiltinUavConfig


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


def test_land_on_a_heaving_pad_touches_down_and_rides_with_it():
    """The ground is the pad on the boat: LAND descends onto it wherever it heaves, the UAV disarms on
    touching it and then moves with it (its velocity the pad's), where on the pad it touched down.
    """
    def pad(t):
        return np.array([0.75, 0.1 * np.sin(0.5 * t), 1.5 + 0.9 * np.sin(0.8 * t)])

    def run(t0, t1):
        states = []
        for k in range(int(round((t1 - t0) * 100.0)) + 1):
            t = t0 + k / 100.0
            states.append((t, uav.step(t, np.zeros(3), pad(t))))
        return states

    uav = BuiltinUav(BuiltinUavConfig(start=(0.75, 0.0, 3.5), start_height=1.0))
    run(0.0, 10.0)
    assert uav.land()[0]
    states = run(10.0, 30.0)
    landed = next(t for t, s in states if not s.armed)
    assert 12.0 < landed < 22.0                                   # 4.5 m above a pad heaving 0.9 m, at 0.5 m/s
    flying = [(t, s) for t, s in states if s.armed]
    assert all(s.position[2] >= pad(t)[2] - 1e-9 for t, s in flying)   # never below the pad
    riding = [(t, s) for t, s in states if t > landed + 0.1]
    offset = riding[0][1].position - pad(riding[0][0])
    assert abs(offset[2]) < 1e-12 and np.hypot(*offset[:2]) < 0.1     # on the pad, near where it was over it
    for t, s in riding:
        np.testing.assert_allclose(s.position, pad(t) + offset, atol=1e-12)
        np.testing.assert_allclose(s.velocity, (pad(t) - pad(t - 0.01)) / 0.01, atol=1e-12)
    assert uav.set_mode('GUIDED')[0] and uav.arm(True)[0] and uav.takeoff(2.0)[0]   # and takes off again
    state = run(30.0, 45.0)[-1][1]
    assert state.armed and state.position[2] > pad(45.0)[2] + 1.0


def test_a_landed_start_over_the_pad_rests_on_it_and_one_beside_it_on_the_level_ground():
    for start, expected in (((0.5, 0.0, 0.0), lambda k: [0.5, 0.0, 2.0 + 0.1 * k]),     # 0.5 m from its centre
                            ((1.5, 0.0, 0.0), lambda k: [1.5, 0.0, 0.0])):          # beyond its 1 m radius
        uav = BuiltinUav(BuiltinUavConfig(start=start))
        for k in range(5):
            state = uav.step(0.01 * k, np.zeros(3), np.array([0.0, 0.0, 2.0 + 0.1 * k]))
            np.testing.assert_allclose(state.position, expected(k))
        assert not state.armed


def test_a_landing_beside_the_pad_comes_down_on_the_level_ground():
    """An abort lands where the UAV is: away from the pad that is the level ground, not the pad's height."""
    uav = BuiltinUav(BuiltinUavConfig(start=(5.0, 0.0, 0.0), start_height=3.0))
    pad = np.array([0.75, 0.0, 1.5])
    for k in range(1001):
        state = uav.step(0.01 * k, np.zeros(3), pad + [0.0, 0.0, 0.5 * np.sin(0.01 * k)])
    assert uav.land()[0]
    for k in range(1001, 3001):
        state = uav.step(0.01 * k, np.zeros(3), pad + [0.0, 0.0, 0.5 * np.sin(0.01 * k)])
    assert not state.armed
    np.testing.assert_allclose(state.position, [5.0, 0.0, 0.0], atol=0.05)
    assert state.position[2] == 0.0 and not state.velocity.any()


WARM_UP_PROBE = r'''
import json
import numpy as np
from uav_bridge.builtin import multirotor_control
from uav_bridge.builtin import uav as builtin_uav
uav = builtin_uav.BuiltinUav(builtin_uav.BuiltinUavConfig(start=(15.0, 0.0, 0.0), start_height=28.0))
def compiled():
    return [len(builtin_uav._fly.signatures), len(multirotor_control._control.signatures)]
before = compiled()
uav.warm_up()
warmed = compiled()
for k in range(1, 4):
    uav.step(0.01 * k, np.array([-1.0, 0.0, -2.0]))
print(json.dumps([before, warmed, compiled()]))
'''


def test_warm_up_compiles_the_flight_and_the_controller_a_flight_then_runs():
    out = subprocess.run([sys.executable, '-c', WARM_UP_PROBE], capture_output=True, text=True, check=True)
    before, warmed, after = json.loads(out.stdout)
    assert before == [0, 0]
    assert warmed == after == [1, 1]
