"""FEM tether against analytic answers: catenary, pendulum period, string waves, energy."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize

from tether_dynamics.fem import constraints, diagnostics, scenes
from tether_dynamics.fem.effects import Drag, KelvinVoigt
from tether_dynamics.fem.end_bodies import Pinned, PointMass
from tether_dynamics.fem.integrators import simulate
from tether_dynamics.fem.model import Scene, Tether, compile_scene, stable_step
from tether_dynamics.fem.statics import hanging_shape

G = 9.81


def _elastic_catenary(length: float, w: float, ea: float, end: np.ndarray):
    """Exact extensible catenary from the origin to end (x, z), parametrised by unstretched s."""

    def shape(h: float, v0: float, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        tz = v0 + w * s
        x = h * s / ea + h / w * (np.arcsinh(tz / h) - np.arcsinh(v0 / h))
        z = (v0 * s + w * s * s / 2) / ea + h / w * (np.sqrt(1 + (tz / h) ** 2) - np.sqrt(1 + (v0 / h) ** 2))
        return x, z
    h, v0 = scipy.optimize.fsolve(lambda p: np.array(shape(p[0], p[1], length)) - end, [20.0, -10.0], xtol=1e-14)
    return lambda s: shape(h, v0, s)


@pytest.mark.parametrize(('element', 'min_order'), [('linear', 1.9), ('quadratic', 2.9)])
def test_static_shape_converges_to_catenary_at_element_order(element: str, min_order: float) -> None:
    length, mu, ea = 10.0, 0.5, 1000.0
    exact = _elastic_catenary(length, mu * G, ea, np.array([8.0, 1.0]))
    errors = []
    for n in (4, 8, 16):
        tet = Tether(length, mu, ea, n, element)
        x = hanging_shape(tet, [0, 0, 0], [8.0, 0.0, 1.0])
        pts, frac = tet.family.interpolate(x, 8)
        xe, ze = exact(frac * tet.l0)
        errors.append(np.max(np.hypot(pts[:, 0] - xe, pts[:, 2] - ze)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > min_order), (errors, orders)


def _crossings(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Times of upward zero crossings, linearly interpolated."""
    i = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def test_small_amplitude_pendulum_period() -> None:
    length, mu, ea, m = 1.0, 0.01, 1e4, 1.0
    tet = Tether(length, mu, ea, 5)
    theta = np.radians(3.0)
    stretched = length * (1 + m * G / ea)
    nodes = np.outer(np.linspace(0, stretched, tet.n_nodes), [np.sin(theta), 0.0, -np.cos(theta)])
    model = compile_scene(Scene(tet, Pinned((0, 0, 0)), PointMass(m), nodes))
    traj = simulate(model, 4.5, 1e-4, record_every=5)
    period = np.mean(np.diff(_crossings(traj.t, traj.nodes[:, -1, 0])))
    inertia = m * stretched**2 + mu * length * stretched**2 / 3
    moment = G * (m * stretched + mu * length * stretched / 2)
    expected = 2 * np.pi * np.sqrt(inertia / moment) * (1 + theta**2 / 16)
    assert period == pytest.approx(expected, rel=2e-3)


def _taut_string(element: str, n: int, shape_fn) -> tuple[Tether, np.ndarray, float]:
    length, span = 1.0, 1.01
    tet = Tether(length, 0.01, 1000.0, n, element)
    s = np.linspace(0.0, 1.0, tet.n_nodes)
    nodes = np.column_stack([span * s, np.zeros_like(s), np.zeros_like(s)]) + shape_fn(s)
    if element == 'quadratic':
        nodes = constraints.project_c1(nodes, n)
    return tet, nodes, span


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_taut_string_transverse_period(element: str) -> None:
    tet, nodes, span = _taut_string(element, 20, lambda s: np.outer(1e-3 * np.sin(np.pi * s), [0, 1, 0]))
    scene = Scene(tet, Pinned((0, 0, 0)), Pinned((span, 0, 0)), nodes, gravity=(0, 0, 0))
    model = compile_scene(scene)
    dt = 0.3 * stable_step(tet, free_ends=0)['dt_rk4']
    traj = simulate(model, 0.2, dt)
    mid = tet.n_nodes // 2
    period = np.mean(np.diff(_crossings(traj.t, traj.nodes[:, mid, 1])))
    tension = tet.ea * (span / tet.length - 1)
    mu_stretched = tet.mu * tet.length / span
    assert period == pytest.approx(2 * span * np.sqrt(mu_stretched / tension), rel=3e-3)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_axial_wave_speed(element: str) -> None:
    tet, nodes, span = _taut_string(element, 20, lambda s: np.outer(1e-4 * np.sin(np.pi * s), [1, 0, 0]))
    model = compile_scene(Scene(tet, Pinned((0, 0, 0)), Pinned((span, 0, 0)), nodes, gravity=(0, 0, 0)))
    dt = 0.3 * stable_step(tet, free_ends=0)['dt_rk4']
    traj = simulate(model, 0.03, dt)
    mid = tet.n_nodes // 2
    disp = traj.nodes[:, mid, 0] - span / 2
    period = np.mean(np.diff(_crossings(traj.t, disp)))
    speed = 2 * tet.length / period
    assert speed == pytest.approx(np.sqrt(tet.ea / tet.mu), rel=3e-3)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
@pytest.mark.parametrize('body', ['point', 'rigid'])
def test_energy_conserved_without_damping(element: str, body: str) -> None:
    model = compile_scene(scenes.pendulum(element, 5, body))
    traj = simulate(model, 2.0, 1e-4, record_every=10)
    d = diagnostics.compute(model, traj)
    assert np.max(np.abs(d.total - d.total[0])) < 1e-5 * d.kinetic.max()
    assert d.kinetic.max() > 10.0
    assert np.max(d.rotation_error) < 1e-12
    assert np.max(d.constraint_position) < 1e-9


@pytest.mark.parametrize('effect', ['kelvin_voigt', 'drag'])
def test_energy_decreases_with_damping(effect: str) -> None:
    kwargs = {'damping': KelvinVoigt(20.0)} if effect == 'kelvin_voigt' else {'drag': Drag(0.0047)}
    model = compile_scene(scenes.pendulum('linear', 5, 'point', **kwargs))
    traj = simulate(model, 2.0, 1e-4, record_every=10)
    d = diagnostics.compute(model, traj)
    assert np.all(np.diff(d.total) < 1e-6 * d.kinetic.max())
    assert d.total[-1] < d.total[0] - 1e-3 * d.kinetic.max()


def test_stable_step_reports_moordyn_rule() -> None:
    tet = Tether(scenes.PENDULUM_LENGTH, 0.03, 1000.0, 5)
    est = stable_step(tet)
    assert est['omega_moordyn'] == pytest.approx(10 / 5.875 * np.sqrt(1000 / 0.03))
    assert est['omega_moordyn'] < est['omega_max'] < 2.0 * est['omega_moordyn']
    assert est['dt_rk4'] == pytest.approx(2 * np.sqrt(2) / est['omega_max'])
