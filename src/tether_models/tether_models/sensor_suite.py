"""The simulated sensor suite of the reel computer, stepped at the IMU rate (thesis Table 5.1, Sec. 6.4).

One :class:`SensorSuite` holds the reel IMU (on the platform, ``boat`` frame), the UAV IMU
(``uav`` frame, FLU, level: the UAV is taken near hover, thesis Sec. 4.4) and the RTK dGPS
receiver (:mod:`tether_models.dgps`). ``step(t, truth)`` takes the ground truth at tick
``t`` and returns the IMU samples of that tick, the dGPS messages that arrive by ``t`` and
every fault injected. Optional stepper vibration (:mod:`tether_models.stepper_vibration`) is
added to the reel IMU's platform-normal axis. An IMU sample can be made non-finite
(``imu_nonfinite_rate``), a fault the estimator must catch.

Each part draws from its own generator seeded with ``[seed, n]``, so enabling one effect
leaves the others' random streams unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field

import numpy as np

from tether_common.rotation import matrix_to_quaternion
from tether_models.dgps import DgpsConfig
from tether_models.dgps import DgpsReceiver
from tether_models.dgps import Fault
from tether_models.dgps import Fix
from tether_models.imu import ImuModel
from tether_models.imu import imu_class
from tether_models.imu import specific_force
from tether_models.stepper_vibration import StepperVibration


_LEVEL = np.eye(3)
"""The UAV IMU's attitude: level (module docstring)."""


@dataclass
class Truth:
    """Ground truth at one tick (SI, ``world`` ENU unless said otherwise)."""

    reel_rotation: np.ndarray
    """(3, 3) ``boat`` to ``world``."""
    reel_angular_velocity: np.ndarray
    """rad/s in ``boat``."""
    reel_acceleration: np.ndarray
    relative_position: np.ndarray
    """UAV attachment minus guide way."""
    relative_acceleration: np.ndarray
    slider_velocity: np.ndarray
    """m/s, the three sliders (for the stepper vibration)."""
    relative_velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """m/s, only for republishing the truth; the sensors do not use it."""


@dataclass
class ImuSample:
    """One IMU message's content: attitude (x, y, z, w), rad/s, m/s^2, body frame."""

    t: float
    quaternion: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray


@dataclass(frozen=True)
class SuiteConfig:
    """IMU classes and the optional effects; dGPS figures in :class:`DgpsConfig`."""

    rate: float = 100.0
    reel_imu: str = 'gx5_25'
    uav_imu: str = 'mpu9250'
    imu_nonfinite_rate: float = 0.0
    vibration_amplitude: float = 0.0
    vibration_resonance: float = 20.0
    vibration_damping: float = 0.1
    step_length: float = 4e-4
    imu_cutoff: float = 41.0


@dataclass
class SuiteOutput:
    """What the sensors publish for one tick."""

    reel: ImuSample
    uav: ImuSample
    fixes: list[Fix]
    faults: list[tuple[str, Fault]]


class SensorSuite:
    """Reel IMU, UAV IMU and dGPS receiver driven by ground truth."""

    def __init__(self, config: SuiteConfig, dgps: DgpsConfig, seed: int) -> None:
        self.config = config
        dt = 1.0 / config.rate
        self.dt = dt
        self.reel_imu = ImuModel(imu_class(config.reel_imu, config.rate), np.random.default_rng([seed, 1]), dt)
        self.uav_imu = ImuModel(imu_class(config.uav_imu, config.rate), np.random.default_rng([seed, 2]), dt)
        self.receiver = DgpsReceiver(dgps, np.random.default_rng([seed, 3]))
        self.vibration = StepperVibration(config.vibration_amplitude, config.vibration_resonance,
                                          config.vibration_damping, config.step_length, config.imu_cutoff,
                                          np.random.default_rng([seed, 4]))
        self.fault_rng = np.random.default_rng([seed, 5])
        self.epoch_ticks = max(1, int(round(config.rate / dgps.rate)))
        self.pending: list[Fix] = []

    def step(self, t: float, truth: Truth) -> SuiteOutput:
        """Sensor outputs of tick ``t`` (s) from the truth at ``t``."""
        faults: list[tuple[str, Fault]] = []
        vib = self.vibration.step(truth.slider_velocity, self.dt) if self.config.vibration_amplitude > 0 else 0.0
        reel_force = specific_force(truth.reel_rotation, truth.reel_acceleration) + np.array([0.0, 0.0, vib])
        gyro, accel = self.reel_imu.measure(truth.reel_angular_velocity, reel_force)
        reel = ImuSample(t, matrix_to_quaternion(truth.reel_rotation), gyro, accel)
        uav_acceleration = truth.reel_acceleration + truth.relative_acceleration
        gyro, accel = self.uav_imu.measure(np.zeros(3), specific_force(_LEVEL, uav_acceleration))
        uav = ImuSample(t, np.array([0.0, 0.0, 0.0, 1.0]), gyro, accel)
        u = self.fault_rng.random(2)
        for name, sample, draw in (('imu_reel', reel, u[0]), ('imu_uav', uav, u[1])):
            if draw < self.config.imu_nonfinite_rate:
                sample.accel[2] = math.nan
                truth_value = truth.reel_acceleration if name == 'imu_reel' else uav_acceleration
                faults.append((name, Fault('nonfinite', t, t, 0, truth_value.copy(), sample.accel.copy())))
        k = int(round(t / self.dt))
        if k % self.epoch_ticks == 0:
            messages, dgps_faults = self.receiver.epoch(t, truth.relative_position)
            self.pending.extend(messages)
            faults.extend(('dgps', f) for f in dgps_faults)
        due = [f for f in self.pending if f.arrival <= t + 1e-9]
        self.pending = [f for f in self.pending if f.arrival > t + 1e-9]
        due.sort(key=lambda f: (f.arrival, f.sequence))
        return SuiteOutput(reel, uav, due, faults)
