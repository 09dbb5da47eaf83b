"""Stepper-motor vibration of the 3-PSR replicator as felt by an IMU on the platform (thesis Sec. 2.8, 6.2).

The thesis blames the filter's worst errors on "actuator noise and resonance of the three
stepper motors" (Sec. 6.2) and noisier IMU readings on stepper vibration at slow speeds
(Sec. 2.7). Each slider's stepper excites the frame at its full-step rate
f_i = |v_i| / step_length; the frame answers as a damped oscillator of natural frequency
``resonance`` and damping ratio ``damping``, normalised so that ``amplitude`` is the
acceleration at resonance; the IMU's anti-alias low pass (first order, ``cutoff``)
attenuates it before sampling. Direction changes of a slider sweep f_i through the low
frequencies, where the response is in band, exactly where the thesis saw the overshoot.
The frame's response to the step impulses is the base-excitation acceleration transfer
2 zeta r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2), r = f / resonance: zero for a motor at rest,
one at resonance, 2 zeta far above it.
"""

from __future__ import annotations

import math

import numpy as np


class StepperVibration:
    """Vertical (platform-normal) vibration acceleration from the three sliders' speeds.

    Args:
        amplitude: m/s^2, response at the frame resonance.
        resonance: Hz, natural frequency of the frame.
        damping: damping ratio of the frame resonance.
        step_length: m of slider travel per full motor step.
        cutoff: Hz, corner of the IMU's anti-alias filter.
        rng: random phases of the three motors at start.
    """

    def __init__(self, amplitude: float, resonance: float, damping: float, step_length: float, cutoff: float,
                 rng: np.random.Generator) -> None:
        self.amplitude = amplitude
        self.resonance = resonance
        self.damping = damping
        self.step_length = step_length
        self.cutoff = cutoff
        self.phase = rng.uniform(0.0, 2.0 * math.pi, 3)

    def gain(self, frequency: np.ndarray) -> np.ndarray:
        """Acceleration per unit ``amplitude`` at a step rate (Hz): frame response times anti-alias gain."""
        r = frequency / self.resonance
        response = 2.0 * self.damping * r**2 / np.sqrt((1.0 - r**2) ** 2 + (2.0 * self.damping * r) ** 2)
        return response / np.sqrt(1.0 + (frequency / self.cutoff) ** 2)

    def step(self, slider_velocity: np.ndarray, dt: float) -> float:
        """Advance the motor phases by ``dt`` s at the given slider speeds (m/s); vibration (m/s^2) at the end."""
        frequency = np.abs(np.asarray(slider_velocity, dtype=float)) / self.step_length
        self.phase = np.mod(self.phase + 2.0 * math.pi * frequency * dt, 2.0 * math.pi)
        return float(self.amplitude * np.sum(self.gain(frequency) * np.sin(self.phase)))
