"""Parameters of the platform node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING
from typing import Any

from tether_common.parameters import ParamSpec

if TYPE_CHECKING:
    from psr_platform_sim.simulator import PlatformConfig

PROFILES = ('jonswap', 'boat', 'hpr1', 'hpr2', 'hpr3', 'still', 'workspace')
"""The named motion profiles (:func:`tether_models.waves.named_profile` and the workspace path)."""

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('r', 0.40, 'tower (rail) radius, prototype of Sec. 2.7', 'm', low=0.05, high=10.0, read_only=True),
    ParamSpec('l', 0.39, 'arm length', 'm', low=0.02, high=15.0, read_only=True),
    ParamSpec('d', 0.46, 'platform edge length', 'm', low=0.02, high=15.0, read_only=True),
    ParamSpec('gamma', 30.0, 'ball-joint mounting angle from the rail axis (Eq. 2.12)', 'deg',
              low=0.0, high=90.0, read_only=True),
    ParamSpec('ball_limit', 30.0, 'ball-joint rotation limit; 0 disables the ball-joint constraint', 'deg',
              low=0.0, high=90.0, read_only=True),
    ParamSpec('profile', 'jonswap', 'motion profile: jonswap, boat, hpr1, hpr2, hpr3, still, workspace '
              '(validation path of Sec. 2.7.1), or a time,heave,roll,pitch CSV file (s, m, rad)', read_only=True,
              choices=PROFILES, file_suffix='.csv'),
    ParamSpec('seed', 1, 'seed of the wave phases (jonswap, boat) and of the IMU noise and bias',
              low=0, high=2**31 - 1, read_only=True),
    ParamSpec('sea_state', 4, 'Douglas sea state of the boat profile', low=3, high=4, read_only=True),
    ParamSpec('boat_length', 5.0, 'boat length of the boat profile', 'm', low=3.0, high=7.0, read_only=True),
    ParamSpec('profile_duration', 240.0, 'length of generated profiles; the platform holds the last pose after it',
              's', low=1.0, high=36000.0, read_only=True),
    ParamSpec('ramp_time', 5.0, 'fade-in of the profile from the level neutral pose', 's',
              low=0.0, high=600.0, read_only=True),
    ParamSpec('command_rate', 30.0, 'firmware slider command rate (Sec. 2.8)', 'Hz', low=1.0, high=1000.0,
              read_only=True),
    ParamSpec('actuator_effects', [], 'prototype actuator effects: firmware (constant slider speed between '
              'commands), microstep (slider heights on whole microsteps)', item_type=str,
              choices=('firmware', 'microstep'), read_only=True),
    ParamSpec('microstep', 2.5e-5, 'slider travel per microstep (0.4 mm full step, 16:1)', 'm', low=1e-7, high=0.01,
              read_only=True),
    ParamSpec('state_rate', 100.0, 'rate of /platform/state and /platform/reel_pose', 'Hz', low=1.0, high=1000.0,
              read_only=True),
    ParamSpec('imu_rate', 100.0, 'rate of /platform/imu', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('heave_limit', 1.1, 'half the heave range of the rails (2.2 m in Sec. 2.2.2)', 'm',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('rail_length', 3.5, 'rail length; the level neutral pose puts the sliders at mid-rail', 'm',
              low=0.1, high=200.0, read_only=True),
    ParamSpec('max_slider_speed', 1.5, 'slider speed limit', 'm/s', low=0.01, high=100.0, read_only=True),
    ParamSpec('max_slider_accel', 6.0, 'slider acceleration limit', 'm/s^2', low=0.01, high=1000.0,
              read_only=True),
    ParamSpec('table_steps', 400, 'lookup-table grid steps per slider axis', low=50, high=2000, read_only=True),
    ParamSpec('cache_dir', '', 'lookup-table cache directory; empty: ~/.cache/tethersim/psr', read_only=True),
    ParamSpec('reel_offset', [0.0, 0.0, 0.0], 'reel mount position from the platform centre in the FLU boat '
              'frame (x the bow = corner 1); the world origin is the mount at the level neutral pose', 'm',
              read_only=True),
    ParamSpec('imu_gyro_noise', 0.002, 'IMU angular-rate white noise, standard deviation per sample', 'rad/s',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('imu_accel_noise', 0.02, 'IMU acceleration white noise, standard deviation per sample', 'm/s^2',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('imu_gyro_bias', 0.001, 'standard deviation of the constant gyro bias drawn at start', 'rad/s',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('imu_accel_bias', 0.05, 'standard deviation of the constant accelerometer bias drawn at start',
              'm/s^2', low=0.0, high=100.0, read_only=True),
)


def from_params(params: Mapping[str, Any]) -> PlatformConfig:
    """Build the simulator's typed configuration from the node's parameter values by name (SI, angles in deg).

    The motion is sampled on a grid at the faster of ``state_rate`` and ``imu_rate``: a slower IMU does
    not coarsen the state (on a grid at the IMU's 20 Hz, the 100 Hz state held each sample 50 ms).
    """
    import numpy as np

    from psr_platform_sim.kinematics import Design
    from psr_platform_sim.simulator import PlatformConfig

    p = params
    design = Design(p['r'], p['l'], p['d'], float(np.radians(p['gamma'])),
                    float(np.radians(p['ball_limit'])) if p['ball_limit'] > 0 else float(np.pi))
    offset = tuple(float(v) for v in p['reel_offset'])
    return PlatformConfig(
        design=design, profile=p['profile'], seed=p['seed'], sea_state=p['sea_state'], boat_length=p['boat_length'],
        profile_duration=p['profile_duration'], ramp_time=p['ramp_time'], command_rate=p['command_rate'],
        sample_rate=max(p['state_rate'], p['imu_rate']), heave_limit=p['heave_limit'], rail_length=p['rail_length'],
        max_slider_speed=p['max_slider_speed'], max_slider_accel=p['max_slider_accel'], table_steps=p['table_steps'],
        cache_dir=Path(p['cache_dir']) if p['cache_dir'] else None,
        reel_offset=(offset[0], offset[1], offset[2]), actuator_effects=tuple(p['actuator_effects']),
        microstep=p['microstep'])
