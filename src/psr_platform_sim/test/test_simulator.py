"""The replicator playing profiles without ROS: state, tracking and the IMU model."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from psr_platform_sim.platform_params import PARAMETERS
from psr_platform_sim.platform_params import from_params
from psr_platform_sim.simulator import PlatformSimulator
from psr_platform_sim.simulator import platform_imu
from psr_platform_sim.simulator import thesis_to_rep103
from tether_common.parameters import spec_table
from tether_models.constants import GRAVITY
from tether_models.waves import ProfileError


def _params(tmp_path, **changes):
    values = {spec.name: spec.default for spec in PARAMETERS}
    values.update(cache_dir=str(tmp_path), table_steps=150, profile_duration=30.0)
    values.update(changes)
    return from_params(values)


def test_parameter_defaults_pass_their_own_specification():
    for name, spec in spec_table(PARAMETERS).items():
        assert spec.check(spec.default) is None, name


def test_still_profile_sits_level_at_mid_rail(tmp_path):
    sim = PlatformSimulator(_params(tmp_path, profile='still'))
    s = sim.sample(3.0)
    np.testing.assert_allclose(s.slider_height, 1.75, atol=1e-9)
    np.testing.assert_allclose([s.heave, s.roll, s.pitch, s.yaw, s.surge, s.sway], 0.0, atol=1e-9)
    np.testing.assert_allclose(s.specific_force, [0.0, 0.0, GRAVITY], atol=1e-9)
    np.testing.assert_allclose(s.angular_velocity, 0.0, atol=1e-9)
    np.testing.assert_allclose(s.quaternion, [0.0, 0.0, 0.0, 1.0], atol=1e-9)
    assert s.in_workspace
    imu = platform_imu(3, 0.01, 0.1, 0.002, 0.05)
    gyro, accel = (np.array(a) for a in zip(*(imu.measure(s.angular_velocity, s.specific_force) for _ in range(4000))))
    np.testing.assert_allclose(accel.std(axis=0), 0.1, rtol=0.06)
    np.testing.assert_allclose(gyro.std(axis=0), 0.01, rtol=0.06)
    np.testing.assert_allclose(accel.mean(axis=0), [0.0, 0.0, GRAVITY] + imu.accel_bias, atol=0.006)


def test_heave_profile_is_tracked_and_felt_by_the_imu(tmp_path):
    sim = PlatformSimulator(_params(tmp_path, profile='jonswap', seed=2))
    error = sim.tracking_error()
    assert error['heave'] < 0.005 and error['roll'] < 1e-9 and error['pitch'] < 1e-9
    assert sim.inside.all()
    # specific force along z = g + heave acceleration (the platform stays level)
    heave_accel = np.gradient(np.gradient(sim.centre[:, 2], 1.0 / sim.rate), 1.0 / sim.rate)
    np.testing.assert_allclose(sim.specific_force[5:-5, 2], GRAVITY + heave_accel[5:-5], atol=1e-6)
    assert np.ptp(sim.centre[:, 2]) > 0.5


def test_boat_profile_state_is_consistent(tmp_path):
    sim = PlatformSimulator(_params(tmp_path, profile='hpr1'))
    error = sim.tracking_error()
    assert np.degrees(error['roll']) < 0.5 and np.degrees(error['pitch']) < 0.5
    assert sim.converged.all()
    s = sim.sample(20.0)
    rates = np.gradient(sim.angles, 1.0 / sim.rate, axis=0)[2000]
    np.testing.assert_allclose([s.roll_rate, s.pitch_rate, s.yaw_rate], rates, atol=1e-12)
    # body rates and Euler-angle rates agree to first order for small angles
    assert np.abs(sim.angular_velocity).max() > 0.05


def test_after_the_profile_the_last_pose_is_held(tmp_path):
    sim = PlatformSimulator(_params(tmp_path, profile='hpr2', profile_duration=10.0))
    late, later = sim.sample(50.0), sim.sample(80.0)
    assert late.roll == later.roll
    assert late.heave_rate == 0.0 and np.all(late.slider_velocity == 0.0)


def test_missing_profile_file_raises_profile_error(tmp_path):
    with pytest.raises(ProfileError, match='nothing.csv'):
        PlatformSimulator(_params(tmp_path, profile=str(tmp_path / 'nothing.csv')))


def test_imu_noise_and_bias_are_seeded():
    a = platform_imu(5, 0.01, 0.1, 0.002, 0.05)
    b = platform_imu(5, 0.01, 0.1, 0.002, 0.05)
    c = platform_imu(6, 0.01, 0.1, 0.002, 0.05)
    np.testing.assert_array_equal(a.accel_bias, b.accel_bias)
    assert np.all(a.accel_bias != c.accel_bias)
    assert np.abs(a.gyro_bias).max() < 0.01


def test_workspace_validation_profile_sweeps_the_ball_limited_workspace(tmp_path):
    """Sec. 2.7.1: loops at 25-90 % of the boundary; thesis range roll +-32, pitch -25..35 deg."""
    sim = PlatformSimulator(_params(tmp_path, profile='workspace', table_steps=200))
    assert sim.inside.all()
    roll, pitch = np.degrees(sim.command[:, 1]), np.degrees(sim.command[:, 2])
    assert 0.9 * 30.0 < roll.max() < 0.9 * 34.0 and 0.9 * 30.0 < -roll.min() < 0.9 * 34.0
    assert 0.9 * 34.0 < pitch.max() < 0.9 * 38.0 and 0.9 * 24.0 < -pitch.min() < 0.9 * 27.0
    np.testing.assert_allclose(sim.command[:, 0], 0.0)
    error = sim.tracking_error()
    assert np.degrees(max(error['roll'], error['pitch'])) < 0.05


def test_reel_mount_moves_with_the_platform_from_the_world_origin(tmp_path):
    offset = [0.1, -0.05, 0.3]
    sim = PlatformSimulator(_params(tmp_path, profile='hpr1', reel_offset=offset, profile_duration=20.0))
    np.testing.assert_allclose(sim.reel_position[0], 0.0, atol=1e-9)  # level at the start of the ramp
    s = sim.sample(15.0)
    rotation = sim.rotation[1500]
    expected = sim.centre[1500] + rotation @ offset - offset
    np.testing.assert_allclose(s.position, expected, atol=1e-12)
    np.testing.assert_allclose(Rotation.from_quat(s.quaternion).as_matrix(), rotation, atol=1e-12)


@pytest.mark.parametrize(('roll', 'pitch'), [(10.0, 0.0), (0.0, 10.0), (-8.0, 12.0)])
def test_published_frames_are_enu_and_flu_with_the_bow_east(tmp_path, roll, pitch):
    """Thesis roll > 0 dips starboard (REP-103 roll > 0); thesis pitch > 0 raises the bow (REP-103 pitch < 0)."""
    csv = tmp_path / 'tilt.csv'
    csv.write_text('time,heave,roll,pitch\n0,0,{0},{1}\n10,0,{0},{1}\n'.format(np.radians(roll), np.radians(pitch)))
    sim = PlatformSimulator(_params(tmp_path, profile=str(csv), ramp_time=0.0))
    s = sim.sample(5.0)
    rotation = Rotation.from_quat(s.quaternion).as_matrix()
    bow, port = rotation[:, 0], rotation[:, 1]
    assert bow[0] > 0.9 and port[1] > 0.9  # bow east, port north
    np.testing.assert_allclose(np.degrees(sim.thesis_angles[500, :2]), [roll, pitch], atol=1e-6)
    assert np.sign(port[2]) == np.sign(roll) or roll == 0.0  # starboard down lifts port
    assert np.sign(bow[2]) == np.sign(pitch) or pitch == 0.0
    np.testing.assert_allclose(thesis_to_rep103(*sim.thesis_angles[500]), [s.roll, s.pitch, s.yaw], atol=1e-12)
    assert np.degrees(s.roll) == pytest.approx(roll, abs=0.5) and np.degrees(s.pitch) == pytest.approx(-pitch, abs=0.5)


def test_a_slower_imu_does_not_coarsen_the_motion_the_state_is_sampled_from(tmp_path):
    config = _params(tmp_path, profile='hpr3', state_rate=100.0, imu_rate=20.0)
    assert config.sample_rate == 100.0
    assert _params(tmp_path, state_rate=50.0, imu_rate=200.0).sample_rate == 200.0
    sim = PlatformSimulator(config)
    heave = [sim.sample(t).heave for t in (12.00, 12.01, 12.02)]
    assert heave[0] != heave[1] != heave[2]        # on a 20 Hz grid the three 10 ms ticks had one sample
