"""Path generation (Sec. 2.6): Eq. 2.17 round trips, differences and motion limits."""

from __future__ import annotations

import numpy as np

from psr_platform_sim.kinematics import PROTOTYPE
from psr_platform_sim.kinematics import platform_pose
from psr_platform_sim.kinematics import solve_corners
from psr_platform_sim.path import central_velocity
from psr_platform_sim.path import limit_motion
from tether_models.waves import named_profile


def _poses_inside(generator, count, seed):
    """Exact poses of random slider heights inside the usable table cells."""
    t = generator.table
    rng = np.random.default_rng(seed)
    cells = np.argwhere(generator.region.cells)
    pick = cells[rng.integers(0, len(cells), count)]
    a, b = rng.uniform(0.0, 1.0, (2, count))
    u = t.heights(pick[:, 0], pick[:, 1]) + np.stack([0.0 * a, a, b], axis=-1) * generator.step
    corners, _, _ = solve_corners(PROTOTYPE, u)
    return platform_pose(corners)


def test_eq_2_17_round_trip_is_far_better_than_the_prototype(prototype_generator):
    """Pose -> sliders by the table -> pose; the thesis's prototype tracked within 1.2 deg mean."""
    pose = _poses_inside(prototype_generator, 2000, seed=5)
    relative = prototype_generator.interpolate(pose.roll, pose.pitch)
    back = platform_pose(solve_corners(PROTOTYPE, relative)[0])
    error = np.degrees(np.hypot(back.roll - pose.roll, back.pitch - pose.pitch))
    assert error.mean() < 0.04  # measured 0.025 deg on a 400-step table
    assert error.max() < 0.1


def test_refined_round_trip_is_exact_including_heave(prototype_generator):
    pose = _poses_inside(prototype_generator, 500, seed=6)
    heave = np.random.default_rng(7).uniform(-1.0, 1.0, 500)
    path = prototype_generator.sliders(heave, pose.roll, pose.pitch, heave_limit=1.1)
    assert path.inside.all()
    back = platform_pose(solve_corners(PROTOTYPE, path.heights + prototype_generator.rail_base)[0])
    assert np.abs(back.roll - pose.roll).max() < 1e-9
    assert np.abs(back.pitch - pose.pitch).max() < 1e-9
    assert np.abs(back.p[:, 2] - prototype_generator.neutral_centre - heave).max() < 1e-9


def test_commands_outside_the_workspace_are_clipped_to_it(prototype_generator):
    roll = np.radians([0.0, 60.0, -5.0])
    pitch = np.radians([0.0, 0.0, -70.0])
    path = prototype_generator.sliders(np.array([0.0, 0.0, 2.0]), roll, pitch, heave_limit=1.1)
    np.testing.assert_array_equal(path.inside, [True, False, False])
    assert path.heave[2] == 1.1
    assert prototype_generator.in_region(path.heights - path.heights[:, :1]).all()
    assert np.degrees(path.roll[1]) < 40.0


def test_fourth_order_central_difference_is_exact_for_quartics():
    t = np.linspace(0.0, 2.0, 41)
    x = 3.0 * t**4 - t**3 + 2.0 * t
    v = central_velocity(x[:, None], t[1] - t[0])[:, 0]
    exact = 12.0 * t**3 - 3.0 * t**2 + 2.0
    np.testing.assert_allclose(v[2:-2], exact[2:-2], atol=1e-9)


def test_motion_limits_bound_speed_and_acceleration():
    dt = 1.0 / 30.0
    t = np.arange(0.0, 5.0, dt)
    command = np.stack([np.where(t > 1.0, 1.0, 0.0), 0.5 * np.sin(8.0 * t), 0.0 * t], axis=-1)
    achieved, speeds, limited = limit_motion(command, dt, max_speed=0.8, max_accel=3.0)
    assert limited > 0
    assert np.abs(speeds).max() <= 0.8 + 1e-12
    assert np.abs(np.diff(speeds, axis=0)).max() <= 3.0 * dt + 1e-12
    assert abs(achieved[-1, 0] - 1.0) < 1e-6


def test_hpr_profile_stays_inside_the_workspace_after_clipping(prototype_generator):
    profile = named_profile('hpr3', duration=60.0)
    path = prototype_generator.sliders(profile.heave, profile.roll, profile.pitch, heave_limit=1.1)
    assert path.inside.mean() > 0.9
    relative = path.heights - path.heights[:, :1]
    assert prototype_generator.in_region(relative).all()
    assert np.abs(path.heave).max() <= 1.1
