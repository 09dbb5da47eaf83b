"""Optional effects (wind, drag, damping) and prescribed motion from samples."""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.fem import diagnostics, kernels, scenes
from tether_dynamics.fem.effects import Drag, KelvinVoigt, Wind
from tether_dynamics.fem.end_bodies import Pinned, PointMass, PrescribedMotion
from tether_dynamics.fem.errors import FemError
from tether_dynamics.fem.integrators import simulate
from tether_dynamics.fem.model import Scene, Tether, compile_scene


def _vertical(n: int = 10, element: str = 'linear', **effects) -> Scene:
    tet = Tether(2.0, 0.05, 500.0, n, element)
    k = tet.n_nodes
    nodes = np.column_stack([np.zeros(k), np.zeros(k), -np.linspace(0.0, 2.0 * 1.002, k)])
    return Scene(tet, Pinned((0.0, 0.0, 0.0)), PointMass(0.05), nodes, **effects)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_wind_pushes_the_tether_downwind(element: str) -> None:
    scene = _vertical(element=element, drag=Drag(0.01), wind=Wind((5.0, 0.0, 0.0)), damping=KelvinVoigt(5.0))
    traj = simulate(compile_scene(scene), 1.0, 2e-4, record_every=50)
    assert np.all(traj.nodes[-1, 1:, 0] > 0.0)
    assert np.max(np.abs(traj.nodes[-1, :, 1])) < 1e-9


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_uniform_cross_wind_gives_the_consistent_load_vector(element: str) -> None:
    """A straight string at rest across a uniform wind carries w = 1/2 rho U^2 Cd d per stretched
    length; 2-point Gauss integrates its consistent nodal loads exactly (the pattern of the
    gravity weights), and the generalised forces are Z^T of them.
    """
    still = compile_scene(_vertical(element=element))
    windy = compile_scene(_vertical(element=element, drag=Drag(0.01), wind=Wind((5.0, 0.0, 0.0))))
    extra = kernels.generalized_forces(0.0, windy.y0, windy.mdl) - kernels.generalized_forces(0.0, still.y0, still.mdl)
    w = 0.5 * 1.225 * 5.0**2 * 1.2 * 0.01 * 1.002
    expected = windy.basis.T @ (w / 0.05 * windy.gravity_weights[windy.free])
    np.testing.assert_allclose(extra[:, 0], expected, rtol=1e-9)
    assert np.max(np.abs(extra[:, 1:])) < 1e-12


def test_sheared_wind_is_zero_below_ground() -> None:
    scene = _vertical(drag=Drag(0.01), wind=Wind((5.0, 0.0, 0.0), z_ref=1.0, alpha=0.14, z_ground=0.5))
    model = compile_scene(scene)
    forces = kernels.generalized_forces(0.0, model.y0, model.mdl)
    still = compile_scene(_vertical())
    np.testing.assert_allclose(forces, kernels.generalized_forces(0.0, still.y0, still.mdl), atol=1e-12)


def test_effects_off_leave_forces_unchanged() -> None:
    on = compile_scene(_vertical(drag=Drag(0.01), damping=KelvinVoigt(5.0)))
    off = compile_scene(_vertical())
    np.testing.assert_array_equal(kernels.generalized_forces(0.0, on.y0, on.mdl),
                                  kernels.generalized_forces(0.0, off.y0, off.mdl))


def test_wind_needs_drag() -> None:
    with pytest.raises(FemError, match='through drag'):
        _vertical(wind=Wind((1.0, 0.0, 0.0)))


def test_sampled_prescribed_motion_matches_the_analytic_one() -> None:
    analytic = scenes.boat_motion(heave=0.5, heave_period=4.0, roll_deg=10.0, roll_period=6.0)
    t = np.linspace(0.0, 3.0, 3001)
    sampled = PrescribedMotion.from_samples(t, analytic.position(t), analytic.velocity(t), analytic.acceleration(t))
    tet = Tether(20.0, 0.042, 1000.0, 8)
    runs = []
    for motion in (analytic, sampled):
        start = motion.position(np.array([0.0]))[0]
        nodes = np.linspace(start, [10.0, 0.0, 15.0], tet.n_nodes)
        model = compile_scene(Scene(tet, motion, PointMass(1.0), nodes), t1=3.0)
        runs.append(simulate(model, 3.0, 1e-3, record_every=100))
    assert np.max(np.abs(runs[0].nodes[:, 0] - analytic.position(runs[0].t))) < 1e-6
    assert np.max(np.abs(runs[0].nodes - runs[1].nodes)) < 1e-3


def test_point_mass_thrust_force_lifts_the_end() -> None:
    scene = _vertical()
    lifted = Scene(scene.tether, scene.start, PointMass(0.05, force=(0.0, 0.0, 5.0)), scene.nodes)
    model = compile_scene(lifted)
    traj = simulate(model, 0.2, 2e-4, record_every=100)
    d = diagnostics.compute(model, traj)
    assert traj.nodes[-1, -1, 2] > scene.nodes[-1, 2] + 0.05
    assert d.kinetic[-1] > 0.0
