"""Forward kinematics Eq. 2.1-2.16: residuals, pose, symmetry and physical constraints."""

from __future__ import annotations

import numpy as np

from psr_platform_sim.kinematics import Design
from psr_platform_sim.kinematics import ball_angles
from psr_platform_sim.kinematics import constraint_residuals
from psr_platform_sim.kinematics import feasible
from psr_platform_sim.kinematics import forward
from psr_platform_sim.kinematics import hinge_angles
from psr_platform_sim.kinematics import initial_guess
from psr_platform_sim.kinematics import physical_margins
from psr_platform_sim.kinematics import platform_pose
from psr_platform_sim.kinematics import rotation_from_angles
from psr_platform_sim.kinematics import solve_corners

DESIGN = Design(1.0, 0.975, 1.15, np.radians(30.0))


def _random_heights(count: int, spread: float, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-spread, spread, (count, 3))


def test_constraint_residuals_at_solved_poses_are_below_1e_10():
    heights = _random_heights(5000, 0.6)
    corners, _, converged = solve_corners(DESIGN, heights)
    ok = feasible(DESIGN, heights, corners, converged)
    assert ok.mean() > 0.9
    residual = np.abs(constraint_residuals(DESIGN, heights[ok], corners[ok]))
    assert residual.max() <= 1e-10


def test_level_sliders_give_the_analytic_neutral_pose():
    heights = np.full((1, 3), 0.3)
    pose, corners, ok = forward(DESIGN, heights)
    radius = DESIGN.d / np.sqrt(3.0)
    drop = np.sqrt(DESIGN.l**2 - (DESIGN.r - radius) ** 2)
    assert ok[0]
    np.testing.assert_allclose(np.linalg.norm(corners[0, :, :2], axis=-1), radius, atol=1e-12)
    np.testing.assert_allclose(corners[0, :, 2], 0.3 - drop, atol=1e-12)
    np.testing.assert_allclose([pose.roll[0], pose.pitch[0], pose.yaw[0]], 0.0, atol=1e-12)
    np.testing.assert_allclose(pose.rotation[0], np.eye(3), atol=1e-12)
    # Eq. 2.10: hinge angle between the outward radius c_i - p and the arm: its elevation.
    hinge = np.degrees(hinge_angles(DESIGN, heights, corners))
    np.testing.assert_allclose(hinge, np.degrees(np.arctan2(drop, DESIGN.r - radius)), atol=1e-9)
    # Eq. 2.11 with the axis 30 deg off the rail: arm 20.2 deg off the rail, 9.8 deg off the axis.
    ball = np.degrees(ball_angles(DESIGN, heights, corners))
    np.testing.assert_allclose(ball, 30.0 - np.degrees(np.arctan2(DESIGN.r - radius, drop)), atol=1e-9)


def test_angles_of_eq_2_7_to_2_9_rebuild_the_rotation():
    heights = _random_heights(500, 0.4, seed=1)
    pose, _, ok = forward(DESIGN, heights)
    rebuilt = rotation_from_angles(pose.roll, pose.pitch, pose.yaw)
    assert np.abs(rebuilt[ok] - pose.rotation[ok]).max() < 1e-12
    assert np.degrees(np.abs(pose.roll[ok])).max() > 15.0


def test_mirrored_sliders_mirror_roll_and_keep_pitch():
    heights = _random_heights(300, 0.4, seed=2)
    mirrored = heights[:, [0, 2, 1]]
    pose, _, ok = forward(DESIGN, heights)
    pose_m, _, ok_m = forward(DESIGN, mirrored)
    both = ok & ok_m
    np.testing.assert_allclose(pose_m.roll[both], -pose.roll[both], atol=1e-10)
    np.testing.assert_allclose(pose_m.pitch[both], pose.pitch[both], atol=1e-10)
    np.testing.assert_allclose(pose_m.yaw[both], -pose.yaw[both], atol=1e-10)


def test_common_slider_offset_only_heaves():
    heights = _random_heights(200, 0.4, seed=3)
    pose, _, ok = forward(DESIGN, heights)
    pose_up, _, _ = forward(DESIGN, heights + 0.7)
    np.testing.assert_allclose(pose_up.p[ok] - pose.p[ok], np.tile([0.0, 0.0, 0.7], (ok.sum(), 1)), atol=1e-10)


def test_flipped_platform_is_rejected_by_eq_2_15():
    heights = np.zeros((1, 3))
    guess = initial_guess(DESIGN, heights)
    guess[..., 2] = 0.9  # start above the sliders: Newton finds the platform folded up
    corners, _, converged = solve_corners(DESIGN, heights, guess)
    tower, hinge = physical_margins(DESIGN, heights, corners)
    assert converged[0] and tower[0] > 0 and hinge[0] < 0
    assert not feasible(DESIGN, heights, corners, converged)[0]
    np.testing.assert_allclose(np.abs(constraint_residuals(DESIGN, heights, corners)), 0.0, atol=1e-10)


def test_platform_wider_than_the_towers_is_rejected_by_eq_2_14():
    wide = Design(1.0, 1.0, 2.0)  # circumradius 1.155 > r: the arms would lean outwards
    pose, corners, ok = forward(wide, np.zeros((1, 3)))
    tower, _ = physical_margins(wide, np.zeros((1, 3)), corners)
    assert tower[0] < 0 and not ok[0]


def test_arm_parallel_to_the_rail_sits_on_the_eq_2_14_boundary():
    vertical = Design(1.0, 1.0, np.sqrt(3.0))  # corners right below the sliders
    heights = np.zeros((1, 3))
    corners, _, converged = solve_corners(vertical, heights)
    tower, _ = physical_margins(vertical, heights, corners)
    assert converged[0]
    assert abs(tower[0]) < 1e-9


def test_unreachable_sliders_do_not_converge():
    heights = np.array([[0.0, 3.0, -3.0]])  # farther apart than arms and platform reach
    _, _, converged = solve_corners(DESIGN, heights)
    assert not converged[0]


def test_pose_of_a_hand_built_tilted_platform():
    corners = np.array([[[0.0, 1.0, 0.0], [np.sqrt(3) / 2, -0.5, 0.0], [-np.sqrt(3) / 2, -0.5, 0.0]]])
    roll = np.radians(10.0)
    turned = corners @ rotation_from_angles(roll, 0.0, 0.0).T
    pose = platform_pose(turned)
    np.testing.assert_allclose([pose.roll[0], pose.pitch[0], pose.yaw[0]], [roll, 0.0, 0.0], atol=1e-12)
