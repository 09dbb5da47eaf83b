"""PD controller: anti-windup, the tuned loop's step and ramp responses, 4 Hz radial sampling, Eq. 4.1 wiring."""

from __future__ import annotations

import numpy as np
import pytest

from smart_reel.controller import CatenaryController
from smart_reel.controller import DiscretePid
from smart_reel.controller import SampleHold
from smart_reel.motor import MotorParameters
from smart_reel.motor import current_step
from smart_reel.tuning import MIN_GAIN_MARGIN
from smart_reel.tuning import MIN_PHASE_MARGIN
from smart_reel.tuning import closed_loop_response
from smart_reel.tuning import default_parameters
from smart_reel.tuning import design_plant
from smart_reel.tuning import loop_margins
from smart_reel.tuning import step_metrics
from tether_dynamics.statics.reference_length import reference_length

STEP_OVERSHOOT = 0.10
"""Stated: at most 10 % overshoot on a 0.1 m reference step."""
STEP_SETTLING = 0.2
"""Stated: inside ±2 % of the step within 0.2 s (10 controller periods)."""
RAMP_ERROR = 0.005
"""Stated: following a 0.5 m/s ramp (the surrogate's peak heave rate) within 5 mm after 1 s."""


def test_tuned_step_response_meets_overshoot_and_settling_time():
    t, y, _ = closed_loop_response(default_parameters(), lambda _t: 0.1, 2.0)
    overshoot, settling = step_metrics(t, y, 0.1)
    assert overshoot <= STEP_OVERSHOOT
    assert settling <= STEP_SETTLING
    assert y[-1] == pytest.approx(0.1, abs=0.002)


def test_tuned_ramp_response_follows_within_the_stated_error():
    t, y, ref = closed_loop_response(default_parameters(), lambda tk: 0.5 * tk, 3.0)
    assert np.max(np.abs(y - ref)[t >= 1.0]) <= RAMP_ERROR


def test_tuned_loop_keeps_the_margins_the_tuning_demands():
    params = default_parameters()
    k, tau = design_plant(params, 8.0)
    pm, gm, _ = loop_margins(params['kp'], params['kd'], k, tau, 1.0 / params['control_rate'])
    assert pm >= MIN_PHASE_MARGIN - 0.5
    assert gm >= MIN_GAIN_MARGIN - 0.5


def test_a_detuned_loop_fails_the_step_spec():
    params = dict(default_parameters(), kp=200.0, kd=0.0)
    t, y, _ = closed_loop_response(params, lambda _t: 0.1, 2.0)
    assert step_metrics(t, y, 0.1)[1] > STEP_SETTLING


def test_pd_is_the_thesis_law_and_clips():
    pid = DiscretePid(kp=100.0, kd=2.0, ki=0.0, period=0.02, limit=48.0)
    first = pid.step(0.1)
    assert first.output == pytest.approx(-10.0) and first.d_term == 0.0
    second = pid.step(0.2)
    assert second.output == pytest.approx(-(100.0 * 0.2 + 2.0 * 0.1 / 0.02))
    assert pid.step(10.0).output == -48.0


def test_integral_is_frozen_while_saturated_in_the_error_direction():
    pid = DiscretePid(kp=100.0, kd=0.0, ki=50.0, period=0.02, limit=48.0)
    for _ in range(100):
        out = pid.step(1.0)  # -100 V wanted: saturated
    assert out.saturated and out.output == -48.0
    assert pid.integral == 0.0
    out = pid.step(0.01)  # unsaturated: integrates again
    assert pid.integral == pytest.approx(-50.0 * 0.01 * 0.02)
    assert not out.saturated


def test_voltage_moves_at_most_the_step_limit_from_the_applied_voltage():
    pid = DiscretePid(kp=3000.0, kd=0.0, ki=50.0, period=0.02, limit=48.0, step_limit=18.0)
    assert pid.step(-0.1).output == 18.0  # 300 V wanted
    assert pid.step(-0.1).output == 36.0
    assert pid.step(-0.1).output == 48.0
    reversed_ = pid.step(0.1)  # -300 V wanted from +48 V
    assert reversed_.output == 30.0 and reversed_.saturated
    assert pid.integral == 0.0  # frozen while the step limit holds the output against the error
    assert pid.step(0.1, applied=0.0).output == -18.0  # a brake held the drive at 0 V
    assert pid.step(0.001).output == pytest.approx(-3.0 - 50.0 * 0.001 * 0.02)


def test_step_limit_keeps_a_voltage_step_on_the_turning_motor_within_the_current_limit():
    motor = MotorParameters()
    rate = 10.0  # rad/s at the spool, steady under its back-EMF
    steady = motor.shaft_constant * rate
    for dv in (motor.voltage_step, 2.0 * motor.voltage_step):
        settled = current_step(motor, 0.0, steady - dv, rate, 5.0 * motor.inductance / motor.resistance)
        assert (abs(settled) < motor.current_limit) == (dv == motor.voltage_step)


def test_radial_distance_is_held_between_4_hz_samples():
    hold = SampleHold(0.25)
    values = [hold.update(k * 0.02, float(k)) for k in range(30)]
    assert values[:13] == [0.0] * 13  # t = 0 .. 0.24
    assert values[13] == 13.0  # t = 0.26, first tick after 0.25
    assert values[25] == 25.0 and values[24] == 13.0


def test_catenary_controller_uses_the_reference_model_and_eq_4_1():
    c = CatenaryController(kp=100.0, kd=0.0, ki=0.0, period=0.02, voltage_limit=48.0)
    first = c.step(3.22, 7.0, 0.0, 8.0)
    expected = reference_length(3.22, 7.0, 'poly')
    assert first.reference_length == expected.length and first.reference_model == expected.model
    assert first.filtered_reference == expected.length
    second = c.step(3.22, 7.5, 0.0, 8.0)  # slow: alpha = 0.2
    assert second.alpha == 0.2
    new = reference_length(3.22, 7.5, 'poly').length
    assert second.filtered_reference == pytest.approx(0.8 * expected.length + 0.2 * new)
    assert second.voltage == pytest.approx(-100.0 * (8.0 - second.filtered_reference))
    exact = CatenaryController(1000.0, 0.0, 0.0, 0.02, 48.0, reference_mode='exact').step(3.22, 7.0, 1.0, 8.0)
    assert exact.reference_model == 'exact'
