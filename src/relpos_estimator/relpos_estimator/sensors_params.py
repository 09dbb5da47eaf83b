"""Parameters of the sensors node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec
from tether_models.dgps import DgpsConfig
from tether_models.imu import IMU_CLASSES
from tether_models.sensor_suite import SuiteConfig

_D = DgpsConfig()
_S = SuiteConfig()

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('seed', 1, 'seed of every sensor error and fault', low=0, high=2**31 - 1, read_only=True),
    ParamSpec('rate', _S.rate, 'IMU rate and tick of the node', 'Hz', low=10.0, high=1000.0, read_only=True),
    ParamSpec('truth', 'plant', 'ground truth of the relative position: plant (/truth/relative) or surrogate '
              '(UAV attachment fixed in world at surrogate_position, the UAV surrogate of Sec. 5.1)',
              choices=('plant', 'surrogate'), read_only=True),
    ParamSpec('surrogate_position', [2.5, 0.0, 5.0], 'UAV attachment in world for truth: surrogate', 'm',
              read_only=True),
    ParamSpec('reel_imu', _S.reel_imu, 'class of the reel IMU (Table 5.1)', choices=IMU_CLASSES, read_only=True),
    ParamSpec('uav_imu', _S.uav_imu, 'class of the UAV IMU (Table 5.1)', choices=IMU_CLASSES, read_only=True),
    ParamSpec('imu_nonfinite_rate', _S.imu_nonfinite_rate, 'probability per IMU sample of a NaN acceleration',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('vibration_amplitude', _S.vibration_amplitude, 'stepper vibration felt by the reel IMU at the '
              'frame resonance; 0 turns the actuator vibration off', 'm/s^2', low=0.0, high=100.0, read_only=True),
    ParamSpec('vibration_resonance', _S.vibration_resonance, 'natural frequency of the replicator frame', 'Hz',
              low=0.1, high=1000.0, read_only=True),
    ParamSpec('vibration_damping', _S.vibration_damping, 'damping ratio of the frame resonance',
              low=0.001, high=2.0, read_only=True),
    ParamSpec('step_length', _S.step_length, 'slider travel per full motor step', 'm', low=1e-6, high=0.1,
              read_only=True),
    ParamSpec('imu_cutoff', _S.imu_cutoff, 'corner of the IMU anti-alias low pass', 'Hz', low=1.0, high=10000.0,
              read_only=True),
    ParamSpec('dgps_rate', _D.rate, 'RTK dGPS output rate (NEO-M8P-2: 4 Hz)', 'Hz', low=0.1, high=100.0,
              read_only=True),
    ParamSpec('dgps_noise', list(_D.noise_std), 'dGPS white noise per axis (ENU), standard deviation', 'm',
              read_only=True),
    ParamSpec('dgps_latency', _D.latency, 'mean delay from time of fix to arrival', 's', low=0.0, high=5.0,
              read_only=True),
    ParamSpec('dgps_latency_jitter', _D.latency_jitter, 'standard deviation of the delay', 's', low=0.0,
              high=5.0, read_only=True),
    ParamSpec('miss_rate', _D.miss_rate, 'probability per epoch of a missed message (Sec. 6.4: 1.35 %)',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('stale_after_miss', _D.stale_after_miss, 'probability that the message after a miss is stale',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('recovery_time', _D.recovery_time, 'time after a miss with RTK float fixes only (Sec. 6.4: ~1 s)',
              's', low=0.0, high=60.0, read_only=True),
    ParamSpec('recovery_noise', _D.recovery_noise, 'noise of the float fixes while recovering', 'm',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('wild_rate', _D.wild_rate, 'probability per epoch of a completely wrong fix', low=0.0, high=1.0,
              read_only=True),
    ParamSpec('wild_min', _D.wild_min, 'smallest error of a wrong fix', 'm', low=0.0, high=1000.0,
              read_only=True),
    ParamSpec('wild_max', _D.wild_max, 'largest error of a wrong fix', 'm', low=0.0, high=1000.0,
              read_only=True),
    ParamSpec('late_rate', _D.late_rate, 'probability per epoch of a message delayed by late_delay',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('late_delay', _D.late_delay, 'extra delay of a late message', 's', low=0.0, high=10.0,
              read_only=True),
    ParamSpec('duplicate_rate', _D.duplicate_rate, 'probability per epoch of a message delivered twice',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('dgps_nonfinite_rate', _D.nonfinite_rate, 'probability per epoch of a NaN altitude',
              low=0.0, high=1.0, read_only=True),
)


def configs(params: dict) -> tuple[SuiteConfig, DgpsConfig]:
    """The suite and receiver configurations of a parameter set."""
    suite = SuiteConfig(rate=params['rate'], reel_imu=params['reel_imu'], uav_imu=params['uav_imu'],
                        imu_nonfinite_rate=params['imu_nonfinite_rate'],
                        vibration_amplitude=params['vibration_amplitude'],
                        vibration_resonance=params['vibration_resonance'],
                        vibration_damping=params['vibration_damping'], step_length=params['step_length'],
                        imu_cutoff=params['imu_cutoff'])
    if len(params['dgps_noise']) != 3:
        raise ValueError(f'dgps_noise: expected 3 values (east, north, up), got {params["dgps_noise"]}')
    if params['wild_max'] < params['wild_min']:
        raise ValueError(f'wild_max {params["wild_max"]} is below wild_min {params["wild_min"]}')
    dgps = DgpsConfig(rate=params['dgps_rate'], noise_std=tuple(params['dgps_noise']),
                      latency=params['dgps_latency'], latency_jitter=params['dgps_latency_jitter'],
                      miss_rate=params['miss_rate'], stale_after_miss=params['stale_after_miss'],
                      recovery_time=params['recovery_time'], recovery_noise=params['recovery_noise'],
                      wild_rate=params['wild_rate'], wild_min=params['wild_min'], wild_max=params['wild_max'],
                      late_rate=params['late_rate'], late_delay=params['late_delay'],
                      duplicate_rate=params['duplicate_rate'], nonfinite_rate=params['dgps_nonfinite_rate'])
    return suite, dgps
