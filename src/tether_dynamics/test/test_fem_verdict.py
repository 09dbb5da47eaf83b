"""The pendulum verdict is chosen from the runs' numbers: contrary runs give contrary sentences."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from tether_dynamics.commands.pendulum import PendulumRun
from tether_dynamics.commands.pendulum import verdict

T = np.linspace(0.0, 10.0, 1001)


def _run_double(element: str, peaks: tuple[float, ...], drift: float = 1e-6) -> PendulumRun:
    """A run whose elastic energy has Gaussian bumps at ``peaks`` and whose total energy drifts by ``drift``."""
    elastic = 0.5 * np.exp(-((T - 2.0) / 0.3) ** 2) + sum(np.exp(-((T - p) / 0.1) ** 2) for p in peaks)
    kinetic = np.full_like(T, 10.0)
    total = 100.0 + drift * 10.0 * T / T[-1]
    diag = SimpleNamespace(t=T, elastic=elastic, kinetic=kinetic, total=total)
    return PendulumRun(element, traj=None, diag=diag, wall=1.0)  # type: ignore[arg-type]


def _claim(lines: list[str]) -> str:
    return lines[-1] if len(lines) < 5 else lines[4]


def test_linear_spikes_only_reproduces_the_contrast():
    lines = verdict([_run_double('linear', (5.8, 7.5)), _run_double('quadratic', ())])
    assert "shows the thesis's contrast" in _claim(lines)
    assert '5.80, 7.50 s' in lines[1] and 'peaks after 5 s: none' in lines[2]


def test_both_spiking_at_the_same_times_does_not_reproduce_it():
    lines = verdict([_run_double('linear', (5.8, 7.5)), _run_double('quadratic', (5.85, 7.45))])
    assert 'with both element types, at nearly the same times' in _claim(lines)


def test_both_spiking_at_different_times_says_so():
    lines = verdict([_run_double('linear', (5.8, 7.5)), _run_double('quadratic', (6.5, 9.0))])
    assert 'with both element types, at different times' in _claim(lines)


def test_quadratic_only_is_the_opposite_and_none_is_no_spike():
    assert 'opposite' in _claim(verdict([_run_double('linear', ()), _run_double('quadratic', (6.0,))]))
    assert 'Neither element type peaks' in _claim(verdict([_run_double('linear', ()), _run_double('quadratic', ())]))


def test_one_element_type_does_not_claim_a_comparison():
    lines = verdict([_run_double('linear', (5.8,))])
    assert lines[-1].strip() == 'Only linear elements were run, so the contrast between element types is not tested; ' \
                                'linear elements do peak after 5 s.'
    assert not any('both element types' in line for line in lines)


def test_energy_drift_is_named_only_when_it_happens():
    calm = verdict([_run_double('linear', ()), _run_double('quadratic', ())])
    assert any('No run diverges' in line for line in calm)
    drifting = verdict([_run_double('linear', (), drift=0.5), _run_double('quadratic', ())])
    assert not any('No run diverges' in line for line in drifting)
    assert any(line.strip().startswith('linear element(s) do not conserve energy') for line in drifting)


def test_step_sensitivity_sentence_follows_the_distances():
    runs = [_run_double('linear', ()), _run_double('quadratic', ())]
    sensitive = verdict(runs, sensitivity={'linear': 0.3, 'linear resisting compression': 1e-5})
    assert 'is sensitive to the step' in sensitive[-1] and 'is not:' in sensitive[-1]
    converged = verdict(runs, sensitivity={'linear': 0.001})
    assert 'converged in the step' in converged[-1]
