"""Inertial measurement unit model shared by the platform simulator and the sensors node.

An IMU measures the angular velocity and the specific force f = R^T (a + g z) of its
body, both in the body frame (REP-103 FLU), plus per-axis errors:

* white noise of standard deviation ``noise_density * sqrt(rate / 2)`` (the datasheet's
  noise density integrated over the Nyquist band),
* a turn-on bias drawn once (the datasheet's initial tolerance taken as 3 sigma),
* a bias drift: a first-order Gauss-Markov process of correlation time ``drift_time`` whose
  stationary standard deviation is the bias instability.

The two classes of thesis Table 5.1 are :data:`MPU9250` (IMU-1, InvenSense MPU-9250) and
:data:`GX5_25` (IMU-2, LORD MicroStrain 3DM-GX5-25). Noise densities and initial
tolerances are the datasheets'; the MPU-9250 datasheet gives no bias instability, so ten
times the 3DM-GX5-25's is assumed.

Random numbers come from the generator handed in, drawn in a fixed order: the three gyro
biases, the three accelerometer biases at construction; then per sample three gyro noises,
three accelerometer noises, and the six drift increments only when drift is on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tether_models.constants import GRAVITY

_MG = GRAVITY * 1e-3
_DEG = math.pi / 180.0


@dataclass(frozen=True)
class ImuSpec:
    """Error figures of one IMU class, SI units, per axis (standard deviations)."""

    gyro_noise: float
    """rad/s, white noise per sample."""
    accel_noise: float
    """m/s^2, white noise per sample."""
    gyro_bias: float
    """rad/s, turn-on bias."""
    accel_bias: float
    """m/s^2, turn-on bias."""
    gyro_drift: float = 0.0
    """rad/s, stationary bias drift (bias instability)."""
    accel_drift: float = 0.0
    """m/s^2, stationary bias drift (bias instability)."""
    drift_time: float = 100.0
    """s, correlation time of the drift."""


def datasheet_spec(rate: float, gyro_density_dps: float, accel_density_ug: float, gyro_initial_dps: float,
                   accel_initial_mg: float, gyro_instability_dph: float, accel_instability_mg: float) -> ImuSpec:
    """Per-sample figures at ``rate`` (Hz) from datasheet units (deg/s/sqrt(Hz), ug/sqrt(Hz), deg/s, mg, deg/h, mg)."""
    band = math.sqrt(rate / 2.0)
    return ImuSpec(
        gyro_noise=gyro_density_dps * _DEG * band,
        accel_noise=accel_density_ug * 1e-3 * _MG * band,
        gyro_bias=gyro_initial_dps * _DEG / 3.0,
        accel_bias=accel_initial_mg * _MG / 3.0,
        gyro_drift=gyro_instability_dph * _DEG / 3600.0,
        accel_drift=accel_instability_mg * _MG,
    )


def imu_class(name: str, rate: float) -> ImuSpec:
    """The :class:`ImuSpec` of a named class (``mpu9250``, ``gx5_25``, ``ideal``) sampled at ``rate`` Hz."""
    if name == 'mpu9250':
        # PS-MPU-9250A-01: 0.01 deg/s/rtHz, 300 ug/rtHz, ZRO +-5 deg/s, zero-g +-60 mg (x, y).
        return datasheet_spec(rate, 0.01, 300.0, 5.0, 60.0, 80.0, 0.4)
    if name == 'gx5_25':
        # 3DM-GX5-25: 0.005 deg/s/rtHz, 25 ug/rtHz, +-0.08 deg/s, +-2 mg; instability 8 deg/h, 0.04 mg.
        return datasheet_spec(rate, 0.005, 25.0, 0.08, 2.0, 8.0, 0.04)
    if name == 'ideal':
        return ImuSpec(0.0, 0.0, 0.0, 0.0)
    raise ValueError(f'unknown IMU class {name!r}: expected mpu9250, gx5_25 or ideal')


IMU_CLASSES = ('mpu9250', 'gx5_25', 'ideal')


class ImuModel:
    """One IMU: truth plus noise, turn-on bias and bias drift, stepped at a fixed ``dt``."""

    def __init__(self, spec: ImuSpec, rng: np.random.Generator, dt: float = 0.01) -> None:
        self.spec = spec
        self.rng = rng
        self.gyro_bias = rng.normal(0.0, spec.gyro_bias, 3)
        self.accel_bias = rng.normal(0.0, spec.accel_bias, 3)
        self.gyro_drift = np.zeros(3)
        self.accel_drift = np.zeros(3)
        self._decay = math.exp(-dt / spec.drift_time)
        self._drive = math.sqrt(1.0 - self._decay**2)

    def measure(self, angular_velocity: np.ndarray, specific_force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Measured angular velocity (rad/s) and specific force (m/s^2), body frame, for one sample."""
        s = self.spec
        gyro = angular_velocity + self.gyro_bias + self.gyro_drift + self.rng.normal(0.0, s.gyro_noise, 3)
        accel = specific_force + self.accel_bias + self.accel_drift + self.rng.normal(0.0, s.accel_noise, 3)
        if s.gyro_drift > 0.0 or s.accel_drift > 0.0:
            self.gyro_drift = self._decay * self.gyro_drift + self._drive * self.rng.normal(0.0, s.gyro_drift, 3)
            self.accel_drift = self._decay * self.accel_drift + self._drive * self.rng.normal(0.0, s.accel_drift, 3)
        return gyro, accel


def specific_force(rotation: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """Specific force R^T (a + g z) in the body frame from the body-to-world rotation and world acceleration."""
    return rotation.T @ (acceleration + np.array([0.0, 0.0, GRAVITY]))


def vertical_acceleration(quaternion: np.ndarray, accel: np.ndarray) -> float:
    """World-vertical acceleration (m/s^2, gravity removed) from a body-frame specific force and x, y, z, w attitude."""
    x, y, z, w = quaternion
    # third row of the body-to-world rotation matrix of the unit quaternion
    row = np.array([2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)])
    return float(row @ accel) - GRAVITY
