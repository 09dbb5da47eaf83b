"""Workspace table (Sec. 2.4), its cache, and the ball-joint optimum of Table 2.3."""

from __future__ import annotations

import numpy as np

from psr_platform_sim.kinematics import Design
from psr_platform_sim.workspace import WorkspaceTable
from psr_platform_sim.workspace import ball_region
from psr_platform_sim.workspace import build_table
from psr_platform_sim.workspace import cached_table
from psr_platform_sim.workspace import nominal_region


def test_table_is_symmetric_in_roll(thesis_table):
    t = thesis_table
    both = t.feasible & t.feasible.T
    np.testing.assert_allclose(t.roll.T[both], -t.roll[both], atol=1e-9)
    np.testing.assert_allclose(t.pitch.T[both], t.pitch[both], atol=1e-9)


def test_table_round_trips_through_the_cache(tmp_path):
    design = Design(1.0, 1.0, 1.0)
    built = cached_table(design, 40, tmp_path)
    files = list(tmp_path.glob('table-*.npz'))
    assert len(files) == 1
    loaded = WorkspaceTable.load(files[0])
    assert loaded.design == built.design
    for name in ('roll', 'pitch', 'yaw', 'centre', 'feasible', 'hinge_margin', 'arm_axial', 'arm_radial'):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(built, name))
    again = cached_table(design, 40, tmp_path)
    np.testing.assert_array_equal(again.roll, built.roll)


def test_ball_joint_optimum_of_table_2_3_design_is_30_deg(thesis_table):
    """Table 2.3 rank 1: l = 0.975, d = 1.15 has its best mounting angle at gamma = 30 deg."""
    gammas = np.arange(20, 46)
    areas = [ball_region(thesis_table, np.radians(g)).area for g in gammas]
    assert gammas[int(np.argmax(areas))] == 30
    # Thesis: 2816.5 deg^2; the fold-based cut (no hand-drawn polygon) gives ~1.4 % less.
    assert abs(max(areas) - 2816.5) / 2816.5 < 0.05


def test_ball_limited_ranges_match_the_thesis(thesis_table):
    """Sec. 2.5.2: roll -32..32 deg, pitch -25..35 deg."""
    region = ball_region(thesis_table)
    roll = np.degrees(thesis_table.roll[region.points])
    pitch = np.degrees(thesis_table.pitch[region.points])
    assert abs(roll.max() - 32.0) < 1.5 and abs(roll.min() + 32.0) < 1.5
    assert abs(pitch.min() + 25.0) < 1.5
    assert abs(pitch.max() - 35.0) < 2.5
    assert region.components == 1


def test_nominal_region_excludes_kinematic_lock_and_keeps_the_hinge_limit(thesis_table):
    region = nominal_region(thesis_table)
    assert np.all(thesis_table.hinge_margin[region.points] >= 0.45)
    assert np.all(thesis_table.feasible[region.points])
    assert region.points.sum() < thesis_table.feasible.sum()
    assert region.area > ball_region(thesis_table).area


def test_suboptimal_design_of_fig_2_3b_has_a_disjoint_workspace():
    table = build_table(Design(1.0, 1.1, 1.15), 120)
    assert nominal_region(table).components > 1
