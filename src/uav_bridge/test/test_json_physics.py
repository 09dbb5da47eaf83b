"""The JSON physics core: servo packets, the quad X motor model, frame semantics, body-frame signs."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from tether_dynamics.plant import bodies
from tether_models.constants import GRAVITY
from uav_bridge import frames
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import JsonPhysicsConfig
from uav_bridge.json_physics.model import UavFrame
from uav_bridge.json_physics.protocol import MAGIC_16
from uav_bridge.json_physics.protocol import MAGIC_32
from uav_bridge.json_physics.protocol import ServoPacket
from uav_bridge.json_physics.protocol import SitlJsonError
from uav_bridge.json_physics.protocol import encode_servo
from uav_bridge.json_physics.protocol import parse_servo
from uav_bridge.json_physics.quad_motors import QuadXConfig
from uav_bridge.json_physics.quad_motors import QuadXMotors
from uav_bridge.json_physics.server import StraightTether
from uav_bridge.json_physics.server import heaving_platform

G = GRAVITY


def packet(count, pwm=(1000, 1000, 1000, 1000), rate=400, channels=16):
    return encode_servo(ServoPacket(rate, count, tuple(pwm) + (0,) * (channels - 4)))


def state(reply):
    return json.loads(reply.data)


def test_servo_packets_of_16_and_32_channels():
    data16 = packet(7, (1100, 1200, 1300, 1400))
    assert len(data16) == 40 and int.from_bytes(data16[:2], 'little') == MAGIC_16
    p = parse_servo(data16)
    assert (p.frame_rate, p.frame_count, p.pwm[:4], len(p.pwm)) == (400, 7, (1100, 1200, 1300, 1400), 16)
    data32 = packet(8, channels=32)
    assert len(data32) == 72 and int.from_bytes(data32[:2], 'little') == MAGIC_32
    assert len(parse_servo(data32).pwm) == 32


@pytest.mark.parametrize(('data', 'words'), [
    (b'', 'too short'), (b'\x00\x00' + bytes(38), 'magic 0'), (packet(1)[:39], 'expected 40'),
    (packet(1, channels=32)[:40], 'expected 72'), (packet(1, rate=0), 'frame_rate 0')])
def test_malformed_packets_are_named_and_counted(data, words):
    physics = JsonPhysics(JsonPhysicsConfig())
    with pytest.raises(SitlJsonError, match=words):
        physics.handle(data, np.zeros(3))
    assert physics.counts.rejected == 1 and physics.counts.stepped == 0


def test_motor_model_follows_the_thrust_curve_and_the_time_constant():
    config = QuadXConfig()
    motors = QuadXMotors(config)
    u = 0.6
    pwm = [1000 + 1000 * u] * 4
    steady = motors.steady_speed(pwm)
    motors.step(steady, config.time_constant)
    expected = config.max_thrust * ((1 - config.thrust_expo) * u + config.thrust_expo * u * u)
    assert motors.speed[0] == pytest.approx((1 - math.exp(-1)) * steady[0], rel=1e-12)
    motors.step(steady, 50 * config.time_constant)
    assert motors.thrusts() == pytest.approx([expected] * 4, rel=1e-9)
    thrust, torque = motors.wrench_flu()
    assert thrust == pytest.approx(4 * expected) and torque == pytest.approx(np.zeros(3), abs=1e-12)
    assert config.hover_command(4 * expected) == pytest.approx(u)


def _settle(physics, pwm, frames_=400, force=(0.0, 0.0, 0.0)):
    reply = None
    for _ in range(frames_):
        count = physics.counts.stepped
        reply = physics.handle(packet(count, pwm), np.asarray(force))
    return reply


def _lift(physics, height=20.0):
    physics.body[bodies.BS_POS + 2] += height


def test_at_rest_on_the_ground_the_imu_reads_gravity_upwards():
    physics = JsonPhysics(JsonPhysicsConfig(start=(3.0, 4.0, 1.0), heading=math.radians(90)))
    s = state(_settle(physics, (1000,) * 4, 10))
    assert s['imu']['accel_body'] == pytest.approx([0.0, 0.0, -G])
    assert s['imu']['gyro'] == pytest.approx([0.0, 0.0, 0.0])
    assert s['position'] == pytest.approx([0.0, 0.0, 0.0]) and s['velocity'] == pytest.approx([0.0] * 3)
    assert s['attitude'] == pytest.approx([0.0, 0.0, math.radians(90)])     # nose east
    assert s['quaternion'] == pytest.approx([math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)])
    assert s['timestamp'] == pytest.approx(10 / 400)


def test_free_fall_reads_zero_specific_force_and_a_downward_ned_velocity():
    physics = JsonPhysics(JsonPhysicsConfig())
    _lift(physics)
    s = state(_settle(physics, (1000,) * 4, 200))         # 0.5 s, rotors off
    assert s['imu']['accel_body'] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert s['velocity'][2] == pytest.approx(G * 0.5, rel=1e-3)          # NED: falling is +down
    assert s['position'][2] == pytest.approx(-20.0 + 0.5 * G * 0.25, abs=0.02)


def test_known_attitude_and_thrust_give_frd_specific_force_and_ned_acceleration():
    # Rolled 20 degrees right (NED roll +), heading north, equal thrust: the body accelerates east.
    physics = JsonPhysics(JsonPhysicsConfig())
    _lift(physics)
    roll = math.radians(20.0)
    physics.body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = frames.euler_ned_to_quaternion_enu(roll, 0.0, 0.0)
    u = 0.6
    pwm = (round(1000 + 1000 * u),) * 4
    s = state(_settle(physics, pwm, 200))                  # 0.5 s = 12 motor time constants
    thrust = physics.frame.thrusts.sum()
    assert s['attitude'] == pytest.approx([roll, 0.0, 0.0], abs=1e-9)
    assert s['imu']['accel_body'] == pytest.approx([0.0, 0.0, -thrust / 6.0], rel=1e-3)
    assert s['imu']['gyro'] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert s['velocity'][1] > 0.05 and abs(s['velocity'][0]) < 1e-9              # east, not north
    acc_ned = frames.enu_to_ned(physics.frame.acceleration)
    assert acc_ned[1] == pytest.approx(thrust / 6.0 * math.sin(roll), rel=1e-3)
    assert acc_ned[2] == pytest.approx(G - thrust / 6.0 * math.cos(roll), rel=1e-3)


@pytest.mark.parametrize(('motors_up', 'axis'), [((2, 1), 0), ((0, 2), 1), ((0, 1), 2)])
def test_differential_thrust_turns_the_body_the_way_arducopter_expects(motors_up, axis):
    # left rotors (3 front-left, 2 rear-left) up: roll right (+p); front (1, 3) up: pitch up (+q);
    # CCW rotors (1, 2) up: yaw right (+r). Channels are 0-based here.
    physics = JsonPhysics(JsonPhysicsConfig())
    _lift(physics)
    pwm = [1550] * 4
    for index in motors_up:
        pwm[index] = 1650
    s = state(_settle(physics, pwm, 20))
    gyro = np.asarray(s['imu']['gyro'])
    assert gyro[axis] > 1e-3
    assert np.all(np.abs(np.delete(gyro, axis)) < 1e-6 * abs(gyro[axis]) + 1e-12)


def test_hover_thrust_balances_weight_and_the_tether_pull():
    config = JsonPhysicsConfig()
    pull = 15.0
    weight = config.vehicle.mass * G
    physics = JsonPhysics(config)
    _lift(physics)
    u = config.vehicle.hover_command(weight + pull)
    pwm = (round(1000 + 1000 * u),) * 4
    s = state(_settle(physics, pwm, 400, force=(0.0, 0.0, -pull)))
    thrust = physics.frame.thrusts.sum()
    assert thrust == pytest.approx(weight + pull, abs=0.2)          # the PWM's 1 µs resolution
    # the accelerometer feels thrust and tether alike: in hover it reads -g, as without the tether
    assert s['imu']['accel_body'] == pytest.approx([0.0, 0.0, -G], abs=0.05)
    assert abs(physics.frame.acceleration[2]) < 0.03                # m/s^2: the hover holds


def test_frame_count_resend_gap_and_restart():
    physics = JsonPhysics(JsonPhysicsConfig())
    first = physics.handle(packet(0, (1100,) * 4), np.zeros(3))
    second = physics.handle(packet(1, (1100,) * 4), np.zeros(3))
    assert (first.kind, second.kind) == ('new', 'new')
    again = physics.handle(packet(1, (1900,) * 4), np.zeros(3))       # a resend: answered from the cache
    assert again.kind == 'resend' and again.data == second.data
    assert physics.counts.stepped == 2 and physics.counts.resent == 1
    assert state(again)['timestamp'] == pytest.approx(2 / 400)
    gap = physics.handle(packet(5, (1100,) * 4), np.zeros(3))
    assert gap.kind == 'gap' and physics.counts.lost == 3
    assert state(gap)['timestamp'] == pytest.approx(3 / 400)             # one frame's step, not four
    _lift(physics, 5.0)
    restart = physics.handle(packet(0, (1000,) * 4), np.zeros(3))
    assert restart.kind == 'restart' and physics.counts.restarts == 1
    s = state(restart)
    assert s['position'] == pytest.approx([0.0, 0.0, 0.0]) and s['timestamp'] == pytest.approx(4 / 400)
    assert physics.handle(packet(1), np.zeros(3)).kind == 'new'


def test_reply_keys_are_written_for_sitls_substring_parser():
    physics = JsonPhysics(JsonPhysicsConfig())
    data = physics.handle(packet(0), np.zeros(3)).data.decode()
    assert data.startswith('\n{') and data.endswith('}\n') and data.count('\n') == 2
    assert ' ' not in data
    for key in ('"timestamp":', '"gyro":[', '"accel_body":[', '"position":[', '"velocity":[', '"attitude":[',
                '"quaternion":['):
        assert data.count(key) == 1, key


def test_straight_tether_is_sim_tethers_line_weight_and_penalty_spring():
    platform = heaving_platform(1.0, 8.0)
    assert platform(2.0).position == pytest.approx([0.0, 0.0, 1.0]) and platform(2.0).velocity == pytest.approx(
        [0.0, 0.0, 0.0], abs=1e-12)
    tether = StraightTether(platform, (0.0, 0.0, 0.5), 0.042, 40.0, G, period=0.01)
    frame = UavFrame(0.0, np.array([15.0, 0.0, 30.5]), np.zeros(3), np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]),
                     np.zeros(3), np.array([0.0, 0.0, G]), np.zeros(4), False)
    tether.update(frame)                                         # t = 0: guide way at (0, 0, 0.5)
    chord = np.array([-15.0, 0.0, -30.0])
    length = np.linalg.norm(chord)
    assert tether.force() == pytest.approx(chord / length * 0.042 * length * G)
    short = StraightTether(platform, (0.0, 0.0, 0.5), 0.042, 30.0, G, period=0.01)
    short.update(frame)                                  # 3.54 m beyond the full length: the spring pulls
    assert np.linalg.norm(short.force()) == pytest.approx(0.042 * length * G + 100.0 * (length - 30.0))
