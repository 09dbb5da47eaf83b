"""Shared fixtures: small lookup tables cached per test session."""

from __future__ import annotations

import numpy as np
import pytest

from psr_platform_sim.kinematics import PROTOTYPE
from psr_platform_sim.kinematics import Design
from psr_platform_sim.path import PathGenerator
from psr_platform_sim.workspace import ball_region
from psr_platform_sim.workspace import build_table

THESIS_BALL_DESIGN = Design(1.0, 0.975, 1.15, np.radians(30.0))
"""Table 2.3, rank 1."""


@pytest.fixture(scope='session')
def thesis_table():
    """200 x 200 table of Table 2.3's optimum, the thesis's study grid."""
    return build_table(THESIS_BALL_DESIGN, 200)


@pytest.fixture(scope='session')
def prototype_generator():
    """Path generator of the prototype (r = 0.40 m) on a 400 x 400 table."""
    table = build_table(PROTOTYPE, 400)
    return PathGenerator(table, ball_region(table), rail_base=-1.75)
