"""The tether plant at quasi-static fidelity: elastic catenary, winch, UAV body, contract checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tether_dynamics.plant import (PlantConfig, PlantConfigError, PlantInputs, PlantStepError, ReelConfig,
                                   TetherPlant, UavConfig)
from tether_dynamics.plant import quasi_static
from tether_dynamics.statics import catenary

MU, EA, G = 0.042, 2.0e4, 9.81
UAV = np.array([15.0, 0.0, 30.0])


def _plant(**kw) -> TetherPlant:
    base = {'fidelity': 'quasi_static', 'elements': 20, 'dt': 0.01, 'initial_length': 40.0,
            'guide_way_offset': (0.0, 0.0, 0.0), 'mass_per_length': MU, 'ea': EA,
            'uav': UavConfig(attach_offset=(0.0, 0.0, 0.0))}
    base.update(kw)
    return TetherPlant(PlantConfig(**base))


def test_end_forces_balance_the_weight_and_match_the_catenary() -> None:
    out = _plant().step(0.0, PlantInputs(uav_position=UAV))
    weight = MU * 40.0 * G
    np.testing.assert_allclose(out.force_on_reel + out.force_on_uav, [0.0, 0.0, -weight], atol=1e-9 * weight)
    stretched = 40.0 * (1.0 + 0.5 * (out.tension_reel + out.tension_uav) / EA)
    sol = catenary.solve(15.0, 30.0 - 0.0, stretched, MU * 40.0 / stretched, G)
    assert out.tension_uav == pytest.approx(float(sol.tension_b), rel=1e-9)
    assert out.tension_uav - out.tension_reel == pytest.approx(MU * 40.0 / stretched * G * 30.0, rel=1e-9)
    assert out.departure_angle == pytest.approx(float(sol.alpha), abs=1e-12)
    np.testing.assert_allclose(out.nodes[0], [0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(out.nodes[-1], UAV, atol=1e-9)
    assert out.lowest_point[2] == pytest.approx(float(sol.lowest_z), abs=1e-9)
    assert out.arc_length[-1] == pytest.approx(40.0)
    assert len(out.tensions) == 20
    half_weight = MU * G * 1.0  # dT/ds = mu g sin(theta): at most mu g over half an element
    assert abs(out.tensions[0] - out.tension_reel) <= half_weight
    assert abs(out.tensions[-1] - out.tension_uav) <= half_weight
    assert np.min(out.tensions) >= float(sol.horizontal_tension) * (1 - 1e-9)


def test_a_length_shorter_than_the_chord_stretches_the_tether() -> None:
    out = _plant(initial_length=33.0).step(0.0, PlantInputs(uav_position=UAV))
    chord = math.hypot(15.0, 30.0)
    mean = 0.5 * (out.tension_reel + out.tension_uav)
    stretched = 33.0 * (1.0 + mean / EA)
    assert chord < stretched < chord * (1.0 + 1e-4)
    assert out.tension_uav > 100.0


def test_prescribed_spool_rate_pays_out_radius_times_rate() -> None:
    plant = _plant(reel=ReelConfig(input='spool_rate', spool_radius=0.05))
    for k in range(201):
        out = plant.step(0.01 * k, PlantInputs(uav_position=UAV, spool_rate=4.0))
    # Within the first call the rate ramps from rest to the command (the spool rate is continuous).
    assert out.deployed_length == pytest.approx(40.0 + 0.05 * 4.0 * 2.0, abs=0.05 * 4.0 * 0.01)
    assert out.payout_rate == pytest.approx(0.2)
    assert out.spool_angle == pytest.approx(8.0, abs=0.04)
    mass0 = MU * 150.0
    assert abs(out.total_tether_mass - mass0) <= 1e-12 * mass0


def test_motor_torque_that_balances_the_pull_holds_the_spool() -> None:
    reel = ReelConfig(input='torque', spool_radius=0.05, inertia=0.01)
    hold = -0.05 * _plant(reel=reel).step(0.0, PlantInputs(uav_position=UAV)).tension_reel
    plant = _plant(reel=reel)
    for k in range(301):
        out = plant.step(0.01 * k, PlantInputs(uav_position=UAV, reel_torque=hold))
    assert abs(out.deployed_length - 40.0) < 1e-9
    weaker = plant.step(3.01, PlantInputs(uav_position=UAV, reel_torque=0.5 * hold))
    for k in range(2, 101):
        weaker = plant.step(3.0 + 0.01 * k, PlantInputs(uav_position=UAV, reel_torque=0.5 * hold))
    assert weaker.payout_rate > 0.0
    assert weaker.reel_work < 0.0


def test_reel_stops_at_its_end_stop() -> None:
    plant = _plant(reel=ReelConfig(input='spool_rate', spool_radius=0.1, max_length=41.0))
    for k in range(301):
        out = plant.step(0.01 * k, PlantInputs(uav_position=UAV, spool_rate=10.0))
    assert out.deployed_length == pytest.approx(41.0)
    assert out.at_stop
    assert out.spool_rate == 0.0


def _hover_inputs(plant: TetherPlant, mass: float) -> tuple[PlantInputs, np.ndarray]:
    """Attitude and thrust that cancel weight and the tether's pull at the initial state."""
    probe = plant.step(0.0, PlantInputs(uav_position=UAV))
    need = mass * G * np.array([0.0, 0.0, 1.0]) - probe.force_on_uav
    axis = need / np.linalg.norm(need)
    rot, _ = Rotation.align_vectors([axis], [[0.0, 0.0, 1.0]])
    return PlantInputs(uav_position=UAV, uav_quaternion=rot.as_quat(), uav_thrust=float(np.linalg.norm(need))), need


def test_dynamic_uav_hovers_under_weight_plus_tether_pull() -> None:
    uav = UavConfig(mode='dynamic', mass=2.0, attach_offset=(0.0, 0.0, 0.0))
    probe = _plant(uav=uav)
    inputs, need = _hover_inputs(probe, 2.0)
    plant = _plant(uav=uav)
    out = plant.step(0.0, inputs)
    force = out.force_on_uav
    sol_tension = out.tension_uav
    assert np.linalg.norm(force) == pytest.approx(sol_tension, rel=1e-12)
    np.testing.assert_allclose(need, 2.0 * G * np.array([0, 0, 1.0]) + sol_tension * -force / np.linalg.norm(force),
                               rtol=1e-12)
    for k in range(1, 501):
        out = plant.step(0.01 * k, inputs)
    assert np.linalg.norm(out.uav_position - UAV) < 1e-6
    assert np.linalg.norm(out.uav_acceleration) < 1e-6
    drop = _plant(uav=uav)
    drop.step(0.0, inputs)
    weak = PlantInputs(uav_position=UAV, uav_quaternion=inputs.uav_quaternion, uav_thrust=0.9 * inputs.uav_thrust)
    for k in range(1, 101):
        fell = drop.step(0.01 * k, weak)
    assert fell.uav_position[2] < UAV[2] - 0.1


def test_moment_on_uav_is_arm_cross_force() -> None:
    uav = UavConfig(mode='prescribed', attach_offset=(0.1, 0.0, -0.2))
    out = _plant(uav=uav).step(0.0, PlantInputs(uav_position=UAV))
    np.testing.assert_allclose(out.uav_end, UAV + [0.1, 0.0, -0.2])
    np.testing.assert_allclose(out.moment_on_uav, np.cross([0.1, 0.0, -0.2], out.force_on_uav))


def test_guide_way_rides_on_the_platform_and_clearances_follow_the_sea() -> None:
    rot = Rotation.from_euler('x', 10.0, degrees=True)
    plant = _plant(guide_way_offset=(0.3, 0.0, 0.5), initial_length=60.0)
    out = plant.step(0.0, PlantInputs(platform_position=np.array([1.0, 2.0, 0.4]), platform_quaternion=rot.as_quat(),
                                      uav_position=np.array([20.0, 2.0, 10.0]), sea_surface_height=0.2))
    np.testing.assert_allclose(out.reel_end, [1.0, 2.0, 0.4] + rot.apply([0.3, 0.0, 0.5]))
    assert out.clearance_deck == pytest.approx(out.lowest_point[2] - 0.4)
    assert out.clearance_sea == pytest.approx(out.lowest_point[2] - 0.2)
    assert out.fouling == (out.lowest_point[2] <= 0.2)
    assert out.fouling


@pytest.mark.parametrize(('kw', 'word'), [({'fidelity': 'cubic'}, 'fidelity'), ({'effects': ('rain',)}, 'effects'),
                                          ({'effects': ('wind',)}, 'drag'), ({'ea': -1.0}, 'ea'),
                                          ({'initial_length': 500.0}, 'initial_length')])
def test_bad_configuration_names_the_field(kw: dict, word: str) -> None:
    with pytest.raises(PlantConfigError, match=word):
        _plant(**kw)


def test_bad_inputs_are_refused_with_a_named_error() -> None:
    plant = _plant()
    plant.step(1.0, PlantInputs(uav_position=UAV))
    with pytest.raises(PlantStepError, match='backwards'):
        plant.step(0.5, PlantInputs(uav_position=UAV))
    with pytest.raises(ValueError, match='platform_quaternion'):
        plant.step(2.0, PlantInputs(uav_position=UAV, platform_quaternion=np.array([0.0, 0.0, 0.0, 2.0])))
    with pytest.raises(PlantStepError, match='uav_position'):
        plant.step(2.0, PlantInputs(uav_position=np.array([np.nan, 0.0, 1.0])))


@pytest.mark.parametrize('b', [(15.0, 0.0, 30.0), (0.0, 0.0, 30.0), (20.0, 5.0, -3.0), (33.0, 0.0, 1.0)])
def test_fast_end_tensions_equal_the_full_solution(b: tuple) -> None:
    from tether_dynamics.plant import quasi_static

    a, b = np.array([0.5, -0.5, 1.0]), np.array(b)
    full = quasi_static.solve(a, b, 35.0, MU, EA, G)
    t_a, t_b, tangent = quasi_static.end_tensions(a, b, 35.0, MU, EA, G)
    assert t_a == pytest.approx(full.tension_a, rel=1e-9)
    assert t_b == pytest.approx(full.tension_b, rel=1e-9)
    np.testing.assert_allclose(tangent, full.tangent_b(), atol=1e-9)


def test_shape_points_on_scalar_paths_are_the_solution_s_points() -> None:
    """quasi_static.shape_points (the markers' reference shape) against solve(...).points over random
    ends and lengths: within 1e-7 of the length 0.1 m or more from vertical, equal on a vertical hang.
    """
    rng = np.random.default_rng(11)
    for _ in range(300):
        a = rng.normal(size=3)
        b = a + np.array([*rng.uniform(-30.0, 30.0, 2), rng.uniform(-5.0, 40.0)])
        if math.hypot(*(b - a)[:2]) < 0.1:
            continue
        length = math.dist(a, b) * rng.choice([1.0, 1.0 + 1e-12, 1.05, 1.5])
        for ea in (math.inf, EA):
            expected = quasi_static.solve(a, b, length, MU, ea, G).points(a, 41)
            np.testing.assert_allclose(quasi_static.shape_points(a, b, length, MU, ea, G, 41), expected,
                                       rtol=0.0, atol=1e-7 * length)
    a, b = np.zeros(3), np.array([0.0, 0.0, 5.0])
    np.testing.assert_array_equal(quasi_static.shape_points(a, b, 7.0, MU, EA, G, 21),
                                  quasi_static.solve(a, b, 7.0, MU, EA, G).points(a, 21))
    with pytest.raises(ValueError, match='shorter than'):
        catenary.shape_point(3.0, 4.0, 4.0, 5)
