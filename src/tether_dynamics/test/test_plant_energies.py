"""The energies the plant reports (``/tether/state``): the formulas on a hand-computed chain, and
a tether at rest against the elastic catenary's, integrated densely along its material.
"""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics.plant import PlantConfig, PlantInputs, ReelConfig, TetherPlant, UavConfig
from tether_dynamics.plant import quasi_static
from tether_dynamics.plant.energies import tether_energies

MU, EA, G = 0.042, 2.0e4, 9.81
GUIDE, UAV, LENGTH = np.array([0.0, 0.0, 0.5]), np.array([20.0, 0.0, 10.0]), 26.0


def test_energies_of_a_three_node_chain_by_hand() -> None:
    nodes = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [2.0, 0.0, -1.0]])
    velocities = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 2.0], [0.0, 3.0, 0.0]])
    lumps = np.array([0.5, 1.0, 0.25])
    tensions = np.array([10.0, 20.0])
    arc = np.array([0.0, 1.5, 2.0])
    kinetic, potential, strain = tether_energies(nodes, velocities, lumps, tensions, arc, 9.0, 100.0)
    assert kinetic == pytest.approx(0.5 * (1.0 * 9.0 + 0.25 * 9.0))
    assert potential == pytest.approx(9.0 * (0.5 * 1.0 + 1.0 * 2.0 + 0.25 * -1.0))
    assert strain == pytest.approx((100.0 * 1.5 + 400.0 * 0.5) / 200.0)


def _catenary_energies() -> tuple[float, float]:
    """Potential and strain energy (J) of the elastic catenary of ``LENGTH`` between the ends,
    integrated over 4,000 intervals of its material coordinate.
    """
    shape = quasi_static.solve(GUIDE, UAV, LENGTH, MU, EA, G)
    sol = shape.solution
    points = shape.points(GUIDE, 4001)
    s = np.linspace(0.0, shape.stretched_length, points.shape[0])
    weight = MU * G * LENGTH / shape.stretched_length
    tension = np.hypot(float(sol.horizontal_tension), shape.tension_a * np.sin(float(sol.alpha)) + weight * s)
    stretch = 1.0 / (1.0 + tension / EA)
    material = np.concatenate([[0.0], np.cumsum(0.5 * (stretch[1:] + stretch[:-1]) * np.diff(s))])
    material *= LENGTH / material[-1]
    potential = MU * G * np.trapezoid(points[:, 2], material)
    strain = np.trapezoid(tension**2 / (2.0 * EA), material)
    return float(potential), float(strain)


def _at_rest(fidelity: str, element_length: float):
    """The plant's outputs after both ends were held for 2 s with internal damping."""
    dt = (5e-5 if fidelity == 'quadratic' else 2e-4) * element_length
    cfg = PlantConfig(fidelity=fidelity, element_length=element_length, elements=round(LENGTH / element_length),
                      dt=dt, initial_length=LENGTH, guide_way_offset=tuple(GUIDE), mass_per_length=MU, ea=EA,
                      gravity=G, effects=('damping',), damping=1.0,
                      reel=ReelConfig(input='spool_rate', spool_radius=0.1, max_length=110.0, total_length=150.0),
                      uav=UavConfig(mode='prescribed', attach_offset=(0.0, 0.0, 0.0)))
    plant = TetherPlant(cfg)
    for k in range(201):
        out = plant.step(0.01 * k, PlantInputs(uav_position=UAV))
    return out


@pytest.mark.parametrize('fidelity', ['quasi_static', 'linear', 'quadratic'])
def test_a_tether_at_rest_reports_the_catenary_s_energies(fidelity: str) -> None:
    """26 elements of 1 m at rest: no kinetic energy, and the potential and strain energy within
    their discretisation of the dense catenary's (measured: potential 0.05-0.3 % above, strain
    within 0.08 %; quadratic elements' potential stays 0.05 % above at 0.5 m: the discrete
    chain's equilibrium against the elastic catenary's mean-tension stretch).
    """
    out = _at_rest(fidelity, 1.0)
    potential, strain = _catenary_energies()
    assert out.kinetic_energy < 1e-9
    assert out.potential_energy == pytest.approx(potential, rel=4e-3)
    assert out.strain_energy == pytest.approx(strain, rel=1.5e-3)


@pytest.mark.parametrize('fidelity', ['quasi_static', 'linear'])
def test_the_lumped_potential_energy_converges_to_the_catenary_s(fidelity: str) -> None:
    """Halving the elements' length at least nearly halves the potential energy's error (lumped
    masses on the nodes: second order; measured 3.5 and 2.2 times smaller).
    """
    potential, _ = _catenary_energies()
    coarse, fine = (abs(_at_rest(fidelity, h).potential_energy / potential - 1.0) for h in (1.0, 0.5))
    assert fine < 0.6 * coarse
