"""The whole-run stepper of held inputs (``TetherPlant.run_held``) against the per-call stepper
the plant node uses: the same samples bit for bit, the same errors.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from tether_dynamics.fem import scenes
from tether_dynamics.plant import PlantDivergenceError, PlantInputs, PlantStepError, TetherPlant
from tether_dynamics.plant import fem_reel
from tether_dynamics.plant.config import UavConfig

RELEASE = PlantInputs(uav_position=np.array(scenes.PENDULUM_RELEASE))


def _pendulum(element: str, n: int, effects: tuple[str, ...] = (), dt_share: float = 1.0):  # noqa: ANN202
    cfg = replace(scenes.pendulum_plant(element, n, 1e-6), effects=effects, damping=0.5, wind=(3.0, 1.0, 0.0))
    return replace(cfg, dt=dt_share * fem_reel.accepted_step(cfg))


def _per_call(plant: TetherPlant, times: np.ndarray) -> dict[str, np.ndarray]:
    outs = [plant.step(float(t), RELEASE) for t in times]
    return {name: np.array([getattr(o, name) for o in outs])
            for name in ('uav_position', 'uav_velocity', 'tension_reel', 'tension_uav', 'kinetic_energy',
                         'potential_energy', 'strain_energy')}


@pytest.mark.parametrize('element, n, effects', [('linear', 10, ()), ('linear', 5, ('drag', 'wind', 'damping')),
                                                 ('quadratic', 5, ('drag', 'damping'))])
def test_a_held_run_equals_the_per_call_stepper_bit_for_bit(element: str, n: int, effects: tuple[str, ...]) -> None:
    cfg = _pendulum(element, n, effects)
    times = 0.01 * np.arange(201)
    expected = _per_call(TetherPlant(cfg), times)
    held = TetherPlant(cfg)
    got = held.run_held(times, RELEASE)
    for name, values in expected.items():
        assert np.array_equal(getattr(got, name), values), name
    assert np.max(np.ptp(got.uav_position, axis=0)) > 1.0   # the pendulum swung
    after = held.step(2.01, RELEASE)                      # the plant goes on from where the run ended
    reference = TetherPlant(cfg)
    _per_call(reference, times)
    assert np.array_equal(after.nodes, reference.step(2.01, RELEASE).nodes)


def test_a_held_run_that_diverges_stops_with_the_per_call_steppers_error(monkeypatch) -> None:
    monkeypatch.setattr(fem_reel, 'UNDAMPED_FRACTION', 4.0)
    cfg = _pendulum('linear', 10, dt_share=1.0)
    times = 0.01 * np.arange(301)
    with pytest.raises(PlantDivergenceError) as per_call:
        _per_call(TetherPlant(cfg), times)
    with pytest.raises(PlantDivergenceError) as held:
        TetherPlant(cfg).run_held(times, RELEASE)
    assert str(held.value) == str(per_call.value)
    assert str(held.value).startswith('energy balance residual')


def test_a_held_run_refuses_what_it_cannot_step() -> None:
    cfg = _pendulum('linear', 5)
    prescribed = replace(cfg, uav=UavConfig(mode='prescribed'))
    with pytest.raises(PlantStepError, match="'dynamic' UAV"):
        TetherPlant(prescribed).run_held(np.array([0.0, 0.01]), RELEASE)
    with pytest.raises(PlantStepError, match='increasing'):
        TetherPlant(cfg).run_held(np.array([0.0, 0.02, 0.01]), RELEASE)
