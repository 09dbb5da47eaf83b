"""Element stencils of the FEM tether against the thesis's equations (Sec. 8.3-8.4, App. D)."""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.fem import constraints, elements_linear, elements_quadratic, kernels
from tether_dynamics.fem.end_bodies import Pinned, PointMass, PrescribedMotion
from tether_dynamics.fem.errors import FemError
from tether_dynamics.fem.model import Scene, Tether, compile_scene

FAMILIES = {'linear': elements_linear, 'quadratic': elements_quadratic}


def _wavy(n_nodes: int, length: float, stretch: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = np.zeros((n_nodes, 3))
    x[:, 1] = -np.linspace(0.0, length * stretch, n_nodes)
    return x + 0.01 * length * rng.standard_normal((n_nodes, 3))


def _wavy_string(element: str, n_elem: int, seed: int) -> tuple[Tether, np.ndarray]:
    """A 2 m string (mu 0.03, EA 1 kN) and wavy nodes stretched ~2 %, made c1 for quadratic elements."""
    tet = Tether(2.0, 0.03, 1000.0, n_elem, element)
    x = _wavy(tet.n_nodes, 2.0, 1.02, seed)
    return tet, constraints.project_c1(x, n_elem) if element == 'quadratic' else x


def _stencil_forces(tet: Tether, x: np.ndarray) -> np.ndarray:
    """Nodal elastic forces of the numpy element stencil plus the nodal weights."""
    fam = tet.family
    return fam.internal_forces(x, tet.ea, tet.l0) + fam.gravity_weights(tet.n_elem, tet.mu, tet.l0)[:, None] * [
        0.0, 0.0, -9.81]


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_mass_and_weight_add_up_to_the_string(element: str) -> None:
    fam = FAMILIES[element]
    m = fam.mass_matrix(7, 0.03, 0.5)
    assert m.sum() == pytest.approx(0.03 * 3.5, rel=1e-12)
    assert fam.gravity_weights(7, 0.03, 0.5).sum() == pytest.approx(0.03 * 3.5, rel=1e-12)
    assert np.all(np.linalg.eigvalsh(m) > 0)


def test_linear_mass_matrix_is_eq_8_14() -> None:
    m = elements_linear.mass_matrix(3, 0.06, 1.0)
    expected = 0.01 * np.array([[2, 1, 0, 0], [1, 4, 1, 0], [0, 1, 4, 1], [0, 0, 1, 2]])
    np.testing.assert_allclose(m, expected, rtol=1e-14)


def test_quadratic_element_forces_match_stencil_d12() -> None:
    rng = np.random.default_rng(1)
    l0, ea = 0.8, 1000.0
    r = np.array([[0.0, 0.0, 0.0], [0.42, 0.03, -0.02], [0.83, 0.05, 0.01]]) + 0.01 * rng.standard_normal((3, 3))
    lm = ((-3 - 2 * np.sqrt(3)) * r[0] + 4 * np.sqrt(3) * r[1] + (3 - 2 * np.sqrt(3)) * r[2]) / 3
    lp = ((-3 + 2 * np.sqrt(3)) * r[0] - 4 * np.sqrt(3) * r[1] + (3 + 2 * np.sqrt(3)) * r[2]) / 3
    qm = ea / l0 * (1 - l0 / np.linalg.norm(lm))
    qp = ea / l0 * (1 - l0 / np.linalg.norm(lp))
    q, dq = qp + qm, qp - qm
    stencil = (q / 6 * np.array([[-7, 8, -1], [8, -16, 8], [-1, 8, -7]])
               + 2 * np.sqrt(3) * dq / 3 * np.array([[1, -1, 0], [-1, 0, 1], [0, 1, -1]]))
    np.testing.assert_allclose(elements_quadratic.internal_forces(r, ea, l0), stencil @ r, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_compression_gives_no_force(element: str) -> None:
    fam = FAMILIES[element]
    x = np.outer(np.linspace(0.0, 1.8, fam.n_nodes(4)), [0.6, -0.8, 0.0])
    assert np.allclose(fam.strains(x, 0.5), -0.1)
    assert np.all(fam.internal_forces(x, 1000.0, 0.5) == 0.0)
    assert fam.elastic_energy(x, 1000.0, 0.5) == 0.0


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_forces_are_minus_energy_gradient(element: str) -> None:
    fam = FAMILIES[element]
    l0, ea = 0.5, 1000.0
    x = _wavy(fam.n_nodes(4), 2.0, 1.02, seed=3)
    f = fam.internal_forces(x, ea, l0)
    h = 1e-7
    for i in (1, 2, fam.n_nodes(4) - 1):
        for c in range(3):
            xp, xm = x.copy(), x.copy()
            xp[i, c] += h
            xm[i, c] -= h
            grad = (fam.elastic_energy(xp, ea, l0) - fam.elastic_energy(xm, ea, l0)) / (2 * h)
            assert -grad == pytest.approx(f[i, c], rel=1e-5, abs=1e-6)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_compiled_forces_equal_numpy_stencil(element: str) -> None:
    tet, x = _wavy_string(element, 4, seed=4)
    model = compile_scene(Scene(tet, Pinned(tuple(x[0])), PointMass(0.2), x))
    f = kernels.generalized_forces(0.0, model.y0, model.mdl)
    np.testing.assert_allclose(f, model.basis.T @ _stencil_forces(tet, x)[model.free], rtol=1e-12, atol=1e-12)


def test_c1_rows_vanish_on_a_parabola_and_not_on_a_kink() -> None:
    c = constraints.c1_matrix(3)
    s = np.linspace(0.0, 3.0, 7)
    assert np.max(np.abs(c @ (s**2 + 2 * s))) < 1e-12
    kink = np.abs(s - 1.5)
    assert np.max(np.abs(c @ kink)) > 0.1


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_compiled_accelerations_solve_the_multiplier_system(element: str) -> None:
    tet, x = _wavy_string(element, 4, seed=5)
    model = compile_scene(Scene(tet, Pinned(tuple(x[0])), Pinned(tuple(x[-1])), x))
    dy = np.empty_like(model.y0)
    kernels.rhs(0.0, model.y0, dy, model.mdl)
    free = model.free
    n_c = model.c_all.shape[0]
    m_ff = model.m_all[np.ix_(free, free)]
    c_f = model.c_all[:, free]
    kkt = np.block([[m_ff, c_f.T], [c_f, np.zeros((n_c, n_c))]])
    expected = np.linalg.solve(kkt, np.vstack([_stencil_forces(tet, x)[free], np.zeros((n_c, 3))]))[:free.size]
    n_q = model.basis.shape[1]
    acc = model.basis @ dy[3 * n_q:6 * n_q].reshape(-1, 3)
    np.testing.assert_allclose(acc, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
    if n_c:
        assert np.max(np.abs(c_f @ acc)) < 1e-9 * np.abs(acc).max()


@pytest.mark.parametrize('n_elem', [1, 4])
def test_quadratic_accelerations_with_an_accelerating_end_solve_the_multiplier_system(n_elem: int) -> None:
    """Eq. 8.44 with a kinematic node: [M_ff C_f^T; C_f 0] [a_f; lambda] = [F_f - M_fk a_k; -C_k a_k]."""
    tet, x = _wavy_string('quadratic', n_elem, seed=6)
    a_k = np.array([1.0, -2.0, 3.0])
    start = PrescribedMotion(lambda t: x[0] + 0.5 * np.outer(t**2, a_k), lambda t: np.outer(t, a_k),
                             lambda t: np.outer(np.ones_like(t), a_k))
    model = compile_scene(Scene(tet, start, Pinned(tuple(x[-1])), x), t1=0.1)
    dy = np.empty_like(model.y0)
    kernels.rhs(0.0, model.y0, dy, model.mdl)
    free, kin = model.free, model.kinematic
    n_c = model.c_all.shape[0]
    m_ff, m_fk = model.m_all[np.ix_(free, free)], model.m_all[np.ix_(free, kin)]
    c_f, c_k = model.c_all[:, free], model.c_all[:, kin]
    accel_k = np.array([a_k, np.zeros(3)])
    kkt = np.block([[m_ff, c_f.T], [c_f, np.zeros((n_c, n_c))]])
    rhs = np.vstack([_stencil_forces(tet, x)[free] - m_fk @ accel_k, -c_k @ accel_k])
    expected = np.linalg.solve(kkt, rhs)[:free.size]
    n_q = model.basis.shape[1]
    acc = model.basis @ dy[3 * n_q:6 * n_q].reshape(-1, 3) + model.particular @ accel_k
    np.testing.assert_allclose(acc, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


@pytest.mark.parametrize('n_elem', [1, 2, 7])
@pytest.mark.parametrize('far_pinned', [False, True])
def test_c1_basis_spans_the_constrained_space_with_a_narrow_band(n_elem: int, far_pinned: bool) -> None:
    n_all = 2 * n_elem + 1
    kinematic = np.array([0, n_all - 1] if far_pinned else [0])
    free = np.arange(1, n_all - 1 if far_pinned else n_all)
    c_all = constraints.c1_matrix(n_elem)
    c_f = c_all[:, free]
    z, h = constraints.c1_basis(n_elem, free, kinematic)
    assert z.shape == (free.size, free.size - c_f.shape[0])
    assert h.shape == (free.size, kinematic.size)
    assert np.linalg.matrix_rank(z) == z.shape[1]
    if c_f.size:
        assert np.max(np.abs(c_f @ z)) < 1e-14
        assert np.max(np.abs(c_f @ h + c_all[:, kinematic])) < 1e-14
    assert np.max(np.count_nonzero(z, axis=1)) <= 3
    m_ff = elements_quadratic.mass_matrix(n_elem, 0.03, 0.5)[np.ix_(free, free)]
    rows, cols = np.nonzero(z.T @ m_ff @ z)
    assert np.max(np.abs(rows - cols)) <= 2


def test_quadratic_scene_with_kinked_nodes_is_refused() -> None:
    tet, x = _wavy_string('quadratic', 4, seed=7)
    x[4, 0] += 0.05
    with pytest.raises(FemError, match='violate the c1 constraints'):
        compile_scene(Scene(tet, Pinned(tuple(x[0])), PointMass(0.2), x))
