"""Stability of the moving-reel FEM plant on a hard case (issue 36): a stiff, light tether
(EA 40 kN, 0.01 kg/m, 40 m) between a heaving reel that pays out and reels in at 2.5 m/s and
a far end driven 4 m sideways in 0.6 s (bench/plant_stability's case, not the issue's held-out one).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from tether_dynamics.plant import PlantConfigError, TetherPlant
from tether_dynamics.plant import fem_reel
from tether_dynamics.plant.fem_reel import PlantDivergenceError, accepted_step, stable_step

_SPEC = importlib.util.spec_from_file_location(
    'plant_stability_bench', Path(__file__).resolve().parents[3] / 'bench' / 'plant_stability' / 'run.py')
hard = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(hard)


def _peaks(cfg, duration: float) -> tuple[float, float]:
    """Peak UAV-end tension (N) and the largest tension between nodes (N) over the run."""
    plant = TetherPlant(cfg)
    uav, inside = 0.0, 0.0
    for k in range(int(round(duration / hard.CALL)) + 1):
        out = plant.step(k * hard.CALL, hard.inputs_at(k * hard.CALL))
        uav, inside = max(uav, out.tension_uav), max(inside, float(np.max(out.tensions)))
    return uav, inside


@pytest.mark.parametrize('fidelity, n, damping', [('linear', 40, 0.0), ('linear', 40, 1.0), ('quadratic', 20, 0.0),
                                                   ('quadratic', 20, 1.0)])
def test_the_accepted_step_is_stable_on_the_hard_case(fidelity: str, n: int, damping: float) -> None:
    """At the step the plant accepts, the run finishes under the watchdog, and its peak tension
    is the one at 0.3 of the estimate within what the undamped tether's snaps scatter (a blow-up
    at 0.9 of the estimate reached 4.5 kN against 122 N).
    """
    cfg = hard.config(fidelity, n, damping, 1.0)
    ratio = accepted_step(cfg) / stable_step(cfg)
    assert ratio == pytest.approx(0.9 if damping > 0.0 else 0.5)
    at_limit = hard.run(hard.config(fidelity, n, damping, ratio))
    small = hard.run(hard.config(fidelity, n, damping, 0.3))
    assert at_limit['ended'] == 'ok' and small['ended'] == 'ok'
    assert at_limit['residual_share'] < 0.2
    assert at_limit['peak_uav_N'] < 2.0 * small['peak_uav_N']
    # Damped linear elements: peaks 105-125 N over steps of 0.3 to 0.9 of the estimate; the
    # peak is a snap's, and round-off alone moves it (at 0.9: 114.4 N or 105.5 N with the
    # strain rate computed as (c d.w) / (|d| l0) or c (d.w / l0) / |d|), hence 15 %.
    if damping > 0.0 and fidelity == 'linear':
        assert at_limit['peak_uav_N'] == pytest.approx(small['peak_uav_N'], rel=0.15)


def test_a_step_past_the_margin_is_refused_and_a_blow_up_is_stopped(monkeypatch) -> None:
    with pytest.raises(PlantConfigError, match='stable step'):
        TetherPlant(hard.config('linear', 40, 0.0, 0.6))
    monkeypatch.setattr(fem_reel, 'UNDAMPED_FRACTION', 1.0)
    result = hard.run(hard.config('linear', 40, 0.0, 0.9))
    assert result['ended'].startswith('energy balance residual')
    assert 'of the energy throughput' in result['ended']
    assert '\n' not in result['ended']


def test_splitting_a_partly_slack_quadratic_reel_element_adds_no_tension() -> None:
    """The first split at 2.5 m/s payout cuts a reel element whose Gauss points are at stretch 0.889
    and 1.000: the old extrapolation put 569 N into a tether carrying 3 N, at every step; the
    largest tension between nodes now stays with the linear elements' (20 N).
    """
    _, quadratic = _peaks(hard.config('quadratic', 40, 5.0, 0.5), 1.5)
    _, linear = _peaks(hard.config('linear', 40, 5.0, 0.5), 1.5)
    assert quadratic < 1.5 * linear < 50.0


def test_no_step_returns_non_finite_values() -> None:
    """A node far from node 1 that overflows stops the step (the kernel checked node 1 only)."""
    plant = TetherPlant(hard.config('linear', 10, 1.0, 0.5))
    plant.step(0.0, hard.inputs_at(0.0))
    plant._fem.v[5, 0] = np.inf                       # test-only: an overflowed node mid-tether
    with pytest.raises(PlantDivergenceError, match='non-finite'):
        plant.step(hard.CALL, hard.inputs_at(hard.CALL))
