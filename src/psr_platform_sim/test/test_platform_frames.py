"""Published frames and angles follow REP-103: FLU ``boat`` (x = bow = corner 1) in ENU ``world``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer
from rosbags.typesys import Stores
from rosbags.typesys import get_types_from_msg
from rosbags.typesys import get_typestore
from scipy.spatial.transform import Rotation

from psr_platform_sim.kinematics import rotation_from_angles
from psr_platform_sim.platform_params import PARAMETERS
from psr_platform_sim.platform_params import from_params
from psr_platform_sim.report import tracking_report
from psr_platform_sim.simulator import PlatformSimulator
from psr_platform_sim.simulator import thesis_to_boat
from psr_platform_sim.simulator import thesis_to_rep103
from tether_models.constants import GRAVITY
from tether_models.waves import boat_profile

MSG = Path(__file__).resolve().parents[2] / 'tether_msgs' / 'msg' / 'PlatformState.msg'
TYPE = 'tether_msgs/msg/PlatformState'


@pytest.fixture(scope='module')
def cache(tmp_path_factory):
    """One lookup-table cache for the module's simulators."""
    return tmp_path_factory.mktemp('table')


def _params(cache, **changes):
    values = {spec.name: spec.default for spec in PARAMETERS}
    values.update(cache_dir=str(cache), table_steps=150, profile_duration=20.0)
    values.update(changes)
    return from_params(values)


def _rep103(quaternion):
    return Rotation.from_quat(quaternion).as_euler('ZYX')[::-1]


def _tilt_csv(path, roll, pitch):
    """A constant pose in thesis angles (the profiles' convention)."""
    path.write_text(f'time,heave,roll,pitch\n0,0,{roll},{pitch}\n10,0,{roll},{pitch}\n')
    return str(path)


def test_thesis_axes_become_flu_with_the_bow_on_x():
    """Thesis y' (bow, corner 1) -> boat x, x' (starboard) -> -y, z' -> z; the mechanism's +y -> world +x."""
    thesis = rotation_from_angles(0.2, -0.1, 0.05)
    boat = thesis_to_boat(thesis)
    np.testing.assert_allclose(boat[:, 0], [thesis[1, 1], -thesis[0, 1], thesis[2, 1]], atol=1e-15)
    np.testing.assert_allclose(boat[:, 1], [-thesis[1, 0], thesis[0, 0], -thesis[2, 0]], atol=1e-15)
    np.testing.assert_allclose(thesis_to_boat(np.eye(3)), np.eye(3), atol=1e-15)
    # zero thesis yaw: REP roll = thesis roll, REP pitch = -thesis pitch, REP yaw = 0
    np.testing.assert_allclose(thesis_to_rep103(0.2, -0.1, 0.0), [0.2, 0.1, 0.0], atol=1e-15)
    # with yaw the conventions differ at second order
    assert abs(thesis_to_rep103(0.2, -0.1, 0.05)[0] - 0.2) > 1e-3


def test_published_angles_are_the_rep103_angles_of_the_quaternion(cache):
    sim = PlatformSimulator(_params(cache, profile='hpr1'))
    times = np.arange(0.0, 20.0, 0.13)
    samples = [sim.sample(t) for t in times]
    angles = np.array([[s.roll, s.pitch, s.yaw] for s in samples])
    from_quaternion = np.array([_rep103(s.quaternion) for s in samples])
    np.testing.assert_allclose(angles, from_quaternion, rtol=0.0, atol=1e-9)
    assert np.degrees(np.abs(angles[:, :2]).max()) > 3.0  # the profile moves
    # REP-103 and thesis angles differ beyond rounding while the platform moves
    assert np.degrees(np.abs(angles[:, 1] + np.interp(times, sim.t, sim.thesis_angles[:, 1])).max()) > 0.01
    # rates are the time derivatives of the published angles (central differences on the 100 Hz grid)
    dt = 1.0 / sim.rate
    for t in (7.0, 12.5):
        before, now, after = sim.sample(t - dt), sim.sample(t), sim.sample(t + dt)
        rates = [(getattr(after, a) - getattr(before, a)) / (2 * dt) for a in ('roll', 'pitch', 'yaw')]
        np.testing.assert_allclose([now.roll_rate, now.pitch_rate, now.yaw_rate], rates, rtol=0.0, atol=1e-9)
    # commanded angles are REP-103 too: the boat attitude with zero yaw, so (roll, -pitch) of the profile
    np.testing.assert_allclose(sim.commanded_angles, sim.command[:, 1:] * [1.0, -1.0], atol=1e-12)
    commanded = np.array([[s.commanded_roll, s.commanded_pitch] for s in samples])
    error = np.degrees(np.sqrt(np.mean((angles[:, :2] - commanded) ** 2, axis=0)))
    assert error.max() < 0.1
    assert np.degrees(np.sqrt(np.mean((angles[:, 1] + commanded[:, 1]) ** 2))) > 1.0  # the sign matters


def test_reel_twist_moves_the_reel_pose_over_one_tick(cache):
    """The reel mount's world velocity and the boat's world angular velocity carry each pose to the next."""
    sim = PlatformSimulator(_params(cache, profile='hpr1', reel_offset=[0.3, -0.2, 0.1]))
    dt = 1.0 / sim.rate
    for t in (6.0, 9.0, 12.5):
        now, later = sim.sample(t), sim.sample(t + dt)
        step = now.reel_velocity * dt
        assert np.linalg.norm(step) > 1e-4
        np.testing.assert_allclose(later.position - now.position, step, rtol=0.0, atol=0.05 * np.linalg.norm(step))
        turn = Rotation.from_quat(later.quaternion) * Rotation.from_quat(now.quaternion).inv()
        np.testing.assert_allclose(turn.as_rotvec(), now.world_angular_velocity * dt, rtol=0.0,
                                   atol=0.05 * np.linalg.norm(now.world_angular_velocity * dt))


def test_boat_profile_roll_turns_the_platform_about_the_bow(cache, tmp_path):
    """The profile's roll is the boat's roll about its length; played, it turns ``boat`` about its x axis."""
    beam = boat_profile(4, 5.0, seed=4, duration=20.0, heading=np.radians(90.0))
    head = boat_profile(4, 5.0, seed=4, duration=20.0, heading=0.0)
    # turning the sea from the bow to the beam moves the motion from pitch into roll
    assert beam.roll.std() > 1.4 * head.roll.std() and head.pitch.std() > 1.4 * beam.pitch.std()
    beam.heave[:] = 0.0
    beam.pitch[:] = 0.0
    csv = tmp_path / 'beam.csv'
    beam.save_csv(csv)
    sim = PlatformSimulator(_params(cache, profile=str(csv)))
    samples = [sim.sample(t) for t in np.arange(6.0, 19.0, 0.05)]
    roll = np.array([s.roll for s in samples])
    commanded = np.array([s.commanded_roll for s in samples])
    pitch = np.array([s.pitch for s in samples])
    np.testing.assert_allclose(commanded, np.interp(np.arange(6.0, 19.0, 0.05), beam.t, beam.roll), atol=1e-3)
    assert np.degrees(np.ptp(roll)) > 4.0 and np.abs(pitch).max() < 0.05 * np.abs(roll).max()
    np.testing.assert_allclose(roll, commanded, atol=np.radians(0.1))
    # the body rates are about boat x and equal the roll rate there
    gyro = np.array([s.angular_velocity for s in samples])
    rate = np.array([s.roll_rate for s in samples])
    assert np.abs(gyro[:, 1:]).max() < 0.05 * np.abs(gyro[:, 0]).max()
    np.testing.assert_allclose(gyro[:, 0], rate, atol=0.02 * np.abs(rate).max())
    # the axis of rotation is the bow: the bow stays level, port rises (starboard dips) when roll > 0
    rotation = np.array([Rotation.from_quat(s.quaternion).as_matrix() for s in samples])
    assert np.abs(rotation[:, 2, 0]).max() < 0.05 * np.abs(rotation[:, 2, 1]).max()
    moving = np.abs(roll) > 0.01
    np.testing.assert_array_equal(np.sign(rotation[moving, 2, 1]), np.sign(roll[moving]))


@pytest.mark.parametrize(('roll', 'pitch'), [(10.0, 0.0), (0.0, 10.0), (-8.0, 12.0)])
def test_static_tilt_gives_flu_specific_force(cache, tmp_path, roll, pitch):
    """Specific force R^T (a - g), g = (0, 0, -9.81): REP roll > 0 (starboard down) -> f_y > 0; pitch > 0 -> f_x < 0."""
    sim = PlatformSimulator(_params(cache, profile=_tilt_csv(tmp_path / 'tilt.csv', *np.radians([roll, pitch])),
                                    ramp_time=0.0))
    s = sim.sample(5.0)
    rep_roll, rep_pitch = np.radians(roll), -np.radians(pitch)  # thesis pitch > 0 raises the bow
    np.testing.assert_allclose([s.commanded_roll, s.commanded_pitch], [rep_roll, rep_pitch], atol=1e-12)
    assert s.roll == pytest.approx(rep_roll, abs=np.radians(0.5))
    assert s.pitch == pytest.approx(rep_pitch, abs=np.radians(0.5))
    expected = GRAVITY * np.array([-np.sin(s.pitch), np.sin(s.roll) * np.cos(s.pitch),
                                   np.cos(s.roll) * np.cos(s.pitch)])
    np.testing.assert_allclose(s.specific_force, expected, atol=1e-6)
    np.testing.assert_allclose(s.angular_velocity, 0.0, atol=1e-9)
    if roll:
        assert np.sign(s.specific_force[1]) == np.sign(roll)
    if pitch:
        assert np.sign(s.specific_force[0]) == np.sign(pitch)  # bow up: forward specific force


def test_report_compares_rep103_commanded_and_achieved(cache, tmp_path):
    """The after-run report on a bag of the simulator's states sees the small true tracking error."""
    sim = PlatformSimulator(_params(cache, profile='hpr1'))
    store = get_typestore(Stores.ROS2_JAZZY)
    store.register(get_types_from_msg(MSG.read_text(), TYPE))
    state, header = store.types[TYPE], store.types['std_msgs/msg/Header']
    stamp = store.types['builtin_interfaces/msg/Time']
    with Writer(tmp_path / 'bag', version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        connection = writer.add_connection('/platform/state', TYPE, typestore=store)
        for ns in range(0, 20_000_000_000, 20_000_000):
            s = sim.sample(ns * 1e-9)
            msg = state(
                header=header(stamp=stamp(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000), frame_id='world'),
                slider_height=s.slider_height, slider_velocity=s.slider_velocity, heave=s.heave, roll=s.roll,
                pitch=s.pitch, yaw=s.yaw, surge=s.surge, sway=s.sway, heave_rate=s.heave_rate,
                roll_rate=s.roll_rate, pitch_rate=s.pitch_rate, yaw_rate=s.yaw_rate,
                commanded_heave=s.commanded_heave, commanded_roll=s.commanded_roll,
                commanded_pitch=s.commanded_pitch, in_workspace=s.in_workspace)
            writer.write(connection, ns, store.serialize_cdr(msg, TYPE))
    lines = tracking_report(str(tmp_path / 'bag'), str(tmp_path / 'out'))
    words = lines[0].split()
    roll_error = float(words[words.index('roll') + 1])
    pitch_error = float(words[words.index('pitch') + 1])
    assert roll_error < 0.1 and pitch_error < 0.1
    assert '1000 states' in lines[0]
