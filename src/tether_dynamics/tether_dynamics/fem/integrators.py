"""Time integration of a compiled scene: classic RK4 (the thesis's baseline) and velocity Verlet."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from tether_dynamics.fem import kernels
from tether_dynamics.fem.errors import DivergenceError, FemError
from tether_dynamics.fem.model import Compiled, stable_step

METHODS = {'rk4': kernels.run_rk4, 'verlet': kernels.run_verlet}


@dataclass
class Trajectory:
    """Recorded states of a run.

    Attributes:
        t: (n,) s.
        nodes: (n, n_nodes, 3) positions, m.
        velocities: (n, n_nodes, 3), m/s.
        omega: (n, 3) end body angular velocity, rad/s (zeros without a rigid body).
        rotation: (n, 3, 3) end body rotation matrices.
    """

    t: np.ndarray
    nodes: np.ndarray
    velocities: np.ndarray
    omega: np.ndarray
    rotation: np.ndarray


def unpack(model: Compiled, t: np.ndarray, y: np.ndarray) -> Trajectory:
    """Turn recorded state vectors into node positions / velocities (kinematic ends filled in)."""
    x, v = kernels.unpack_all(np.ascontiguousarray(t), np.ascontiguousarray(y), model.mdl)
    base = 6 * model.basis.shape[1]
    return Trajectory(t.copy(), x, v, y[:, base:base + 3].copy(), y[:, base + 3:base + 12].reshape(-1, 3, 3).copy())


def _cause(model: Compiled, dt: float, method: str, status: int) -> str:
    """Name the likely reason a run left the physical range."""
    limits = stable_step(model.scene.tether, free_ends=model.kinematic.size == 1)
    limit = limits['dt_rk4' if method == 'rk4' else 'dt_verlet']
    if dt > limit:
        return (f'time step {dt:.3g} s is above the stable limit {limit:.3g} s '
                f'(omega_max {limits["omega_max"]:.4g} rad/s); reduce dt')
    what = 'non-finite state' if status == kernels.STATUS_NONFINITE else 'runaway strain'
    return (f'{what} with dt {dt:.3g} s below the stable estimate {limit:.3g} s: a snap load or '
            'prescribed motion too violent for this step, or unphysical parameters')


def simulate(model: Compiled, t_end: float, dt: float, method: str = 'rk4',
             record_every: int = 1, t0: float = 0.0) -> Trajectory:
    """Integrate from t0 to t_end at fixed step dt, recording every ``record_every`` steps.

    Raises:
        DivergenceError: The state became non-finite or a strain exceeded the scene's strain_limit; the
            message names the time, the element and the likely cause.
    """
    if method not in METHODS:
        msg = f"method must be one of {sorted(METHODS)}, got {method!r}"
        raise FemError(msg)
    if not dt > 0 or t_end <= t0 or record_every < 1:
        msg = 'need dt > 0, t_end > t0 and record_every >= 1'
        raise FemError(msg)
    n_steps = int(round((t_end - t0) / dt))
    t_rec, y_rec, n_rec, status, t_fail, elem, strain = METHODS[method](
        model.y0, t0, dt, n_steps, record_every, model.mdl)
    if status != kernels.STATUS_OK:
        raise DivergenceError(t_fail, int(elem), float(strain), _cause(model, dt, method, status))
    return unpack(model, t_rec[:n_rec], y_rec[:n_rec])


def warm_up() -> float:
    """Load (or, on first use on a machine, compile) every kernel; returns the seconds it took."""
    from tether_dynamics.fem.end_bodies import Pinned, PointMass  # noqa: PLC0415 - avoid a cycle
    from tether_dynamics.fem.model import Scene, Tether, compile_scene  # noqa: PLC0415

    start = time.perf_counter()
    tet = Tether(1.0, 0.01, 100.0, 2)
    nodes = np.column_stack([np.zeros(3), np.zeros(3), -np.linspace(0.0, 1.0, 3)])
    model = compile_scene(Scene(tet, Pinned((0.0, 0.0, 0.0)), PointMass(0.1), nodes))
    for method in METHODS:
        simulate(model, 2e-4, 1e-4, method)
    return time.perf_counter() - start
