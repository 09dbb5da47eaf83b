"""Parameters of the platform node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PROFILES = ('jonswap', 'boat', 'hpr1', 'hpr2', 'hpr3', 'still', 'workspace')
"""The named motion profiles (:func:`psr_platform_sim.waves.named_profile` and the workspace path)."""

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
