"""The station controller in closed loop with the plant's UAV rigid body (tether_dynamics.plant.bodies)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tether_dynamics.plant import bodies
from tether_dynamics.plant.config import UavConfig
from tether_models.constants import GRAVITY
from uav_bridge.builtin.multirotor_control import StationController
from uav_bridge.builtin.multirotor_control import UavBodyState

STATION = np.array([15.0, 0.0, 30.0])


def _fly(start, tether_force, seconds=20.0, feed_forward=False, yaw=0.0, start_quaternion=(0.0, 0.0, 0.0, 1.0)):
    """Body stepped at 1 kHz, controller at 100 Hz (commands held between its steps)."""
    uav = UavConfig(mode='dynamic')
    inertia = np.asarray(uav.inertia, float)
    body = np.zeros(bodies.BS_SIZE)
    body[bodies.BS_POS:bodies.BS_POS + 3] = start
    body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = start_quaternion
    controller = StationController(uav.mass, inertia, GRAVITY)
    rho = np.zeros(3)
    track = []
    thrust, torque = 0.0, np.zeros(3)
    for k in range(int(seconds * 1000)):
        t = k * 1e-3
        if k % 10 == 0:
            state = UavBodyState(body[0:3].copy(), body[3:6].copy(), body[6:10].copy(), body[10:13].copy())
            thrust, torque = controller.step(t, state, STATION, yaw, tether_force if feed_forward else None)
            track.append((t, *body[0:3], thrust))
        bodies.body_step(body, uav.mass, inertia, np.linalg.inv(inertia), rho, thrust, torque,
                         np.asarray(tether_force, float), GRAVITY, 1e-3)
    return np.array(track), body, uav


def test_holds_station_against_a_constant_tether_pull():
    pull = np.array([-3.0, 0.0, -2.0])          # the tether pulls toward the reel and down
    track, body, uav = _fly(STATION + [0.0, 0.0, -1.0], pull)
    assert np.linalg.norm(body[0:3] - STATION) < 0.02          # the integral removes the steady offset
    assert np.linalg.norm(body[3:6]) < 0.01
    # thrust balances weight and pull; the thrust axis leans away from the reel by atan(3 / (m g + 2))
    thrust_axis = Rotation.from_quat(body[6:10]).apply([0.0, 0.0, 1.0])
    expected = np.array([3.0, 0.0, uav.mass * GRAVITY + 2.0])
    assert track[-1, 4] == pytest.approx(np.linalg.norm(expected), rel=1e-3)
    np.testing.assert_allclose(thrust_axis, expected / np.linalg.norm(expected), atol=1e-3)


def test_feed_forward_of_the_measured_tether_force_shrinks_the_transient():
    pull = np.array([-6.0, 2.0, -4.0])
    plain, _, _ = _fly(STATION, pull, seconds=10.0)
    fed, _, _ = _fly(STATION, pull, seconds=10.0, feed_forward=True)
    worst_plain = np.max(np.linalg.norm(plain[:, 1:4] - STATION, axis=1))
    worst_fed = np.max(np.linalg.norm(fed[:, 1:4] - STATION, axis=1))
    assert worst_fed < 0.5 * worst_plain        # left: the time the body takes to lean into the pull
    assert worst_plain > 0.1


def test_recovers_from_a_tilted_start_and_turns_to_the_heading():
    tilted = Rotation.from_euler('xyz', [0.4, -0.3, 1.0]).as_quat()
    track, body, _ = _fly(STATION + [2.0, -1.0, 0.5], np.zeros(3), seconds=25.0, yaw=math.pi / 2,
                          start_quaternion=tilted)
    assert np.linalg.norm(body[0:3] - STATION) < 0.02
    forward = Rotation.from_quat(body[6:10]).apply([1.0, 0.0, 0.0])
    np.testing.assert_allclose(forward, [0.0, 1.0, 0.0], atol=1e-3)
    assert np.all(track[:, 4] >= 0.0)
