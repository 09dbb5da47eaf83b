"""Hard cases for the FEM tether: each stays finite with energy and constraints in bounds,
or stops with a DivergenceError naming time, element and cause.
"""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.fem import diagnostics, scenes
from tether_dynamics.fem.end_bodies import Pinned, PointMass
from tether_dynamics.fem.errors import DivergenceError
from tether_dynamics.fem.integrators import simulate
from tether_dynamics.fem.model import Scene, Tether, compile_scene, stable_step
from tether_dynamics.fem.statics import hanging_shape


def _run(scene: Scene, span: float, fraction: float = 0.5, method: str = 'rk4', every: int = 10):
    model = compile_scene(scene, t1=span)
    free_ends = 0 if model.kinematic.size == 2 else 1
    dt = fraction * stable_step(scene.tether, free_ends)['dt_' + method]
    traj = simulate(model, span, dt, method, record_every=every)
    return diagnostics.compute(model, traj)


def _drift(d: diagnostics.Diagnostics) -> float:
    return float(np.max(np.abs(d.total - d.total[0])) / d.kinetic.max())


def _hanging(length: float, mu: float, ea: float, n: int, end, element: str = 'linear', mass: float = 0.432):
    tet = Tether(length, mu, ea, n, element)
    nodes = hanging_shape(tet, [0, 0, 0], end)
    return Scene(tet, Pinned((0, 0, 0)), PointMass(mass), nodes)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_stiff_tether_near_taut(element: str) -> None:
    chord = 0.999 * 5.875
    d = _run(_hanging(5.875, 0.03, 1e4, 10, [chord, 0.0, 0.0], element), 1.0, fraction=0.1)
    assert _drift(d) < 2e-5
    assert np.max(d.strains) < 0.05
    assert np.max(d.constraint_position) < 1e-9


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_slack_tether_snapping_taut(element: str) -> None:
    model = compile_scene(scenes.pendulum(element, 5, 'rigid'))
    d = diagnostics.compute(model, simulate(model, 3.0, 1e-4, record_every=10))
    assert _drift(d) < 1e-5
    slack = d.length < scenes.PENDULUM_LENGTH
    assert np.any(slack) and np.any(~slack)
    assert d.elastic.max() > 20 * d.elastic[0]


def test_very_short_elements() -> None:
    d = _run(_hanging(0.5, 0.03, 1000.0, 50, [0.45, 0.0, -0.1], mass=0.05), 0.2, every=50)
    assert 0.01 == pytest.approx(0.5 / 50)
    assert _drift(d) < 1e-4


def test_long_tether_many_elements() -> None:
    d = _run(_hanging(100.0, 0.042, 1000.0, 100, [60.0, 0.0, 70.0], mass=1.0), 1.0, fraction=0.2, every=20)
    assert _drift(d) < 1e-3
    assert np.all(np.isfinite(d.tension_start)) and np.max(d.tension_start) < 100.0


def test_heavy_end_mass() -> None:
    d = _run(_hanging(5.875, 0.03, 1000.0, 5, list(scenes.PENDULUM_RELEASE), mass=10.0), 3.0)
    assert _drift(d) < 1e-4
    assert 0.2 < np.max(d.strains) < 0.5


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_fast_boat_motion_sea_state_4(element: str) -> None:
    tet = Tether(1.1 * np.hypot(20.0, 29.0), 0.042, 1000.0, 20, element)
    boat = scenes.boat_motion()
    start = boat.position(np.array([0.0]))[0]
    nodes = hanging_shape(tet, start, [20.0, 0.0, 30.0])
    scene = Scene(tet, boat, Pinned((20.0, 0.0, 30.0)), nodes)
    d = _run(scene, 10.0, every=20)
    assert np.max(d.constraint_position) < 1e-5
    assert np.max(d.strains) < 0.05
    assert np.max(np.abs(d.total - d.total[0])) < 50.0
    assert np.ptp(d.angle_start) > 5.0


def test_quadratic_with_constraints_over_60_s() -> None:
    model = compile_scene(scenes.pendulum('quadratic', 5, 'rigid'))
    d = diagnostics.compute(model, simulate(model, 60.0, 5e-4, record_every=100))
    assert np.max(d.constraint_position) < 1e-8
    assert np.max(d.constraint_velocity) < 1e-8
    assert _drift(d) < 5e-3
    assert np.max(d.rotation_error) < 1e-12


@pytest.mark.parametrize('method', ['rk4', 'verlet'])
def test_step_beyond_stable_limit_raises_named_error(method: str) -> None:
    """3x the estimate: it ignores the end mass, so near 1.5x the pendulum is only marginally unstable."""
    scene = scenes.pendulum('linear', 5, 'point')
    model = compile_scene(scene)
    limit = stable_step(scene.tether)['dt_' + method]
    with pytest.raises(DivergenceError, match=r'diverged at t = .* s in element \d+ .*stable limit') as err:
        simulate(model, 2.0, 3.0 * limit, method)
    assert 0.0 < err.value.time < 2.0
    assert 0 <= err.value.element < 5
