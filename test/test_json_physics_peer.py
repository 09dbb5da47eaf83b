"""The JSON physics server over UDP against the SITL test double: lockstep frames, silence, restart, parsing.

The double (``json_sitl_peer_double.py``) covers what the real SITL binary cannot be made to do
on demand: a reply lost on the way, a physics side silent long enough for resends to pile
up, a restart mid-flight, the 32-channel packet. Each frame is driven step by step (send,
serve, receive), so nothing here depends on timing.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from json_sitl_peer_double import SitlJsonPeerDouble
from json_sitl_peer_double import parse_sensors
from tether_dynamics.plant import PlantConfig
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant import UavConfig
from tether_models.constants import GRAVITY
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import JsonPhysicsConfig
from uav_bridge.json_physics.server import JsonPhysicsServer
from uav_bridge.json_physics.server import PlantTether
from uav_bridge.json_physics.server import resting_platform


@pytest.fixture
def link():
    logs = []
    server = JsonPhysicsServer(JsonPhysics(JsonPhysicsConfig(start=(10.0, 0.0, 0.0))), port=0, log=logs.append)
    peer = SitlJsonPeerDouble(server.port, resend_after=0.05)
    yield server, peer, logs
    peer.close()
    server.close()


def serve(server):
    return lambda: server.poll(1.0)


def test_frames_in_lockstep_none_lost_none_duplicated(link):
    server, peer, _ = link
    for _ in range(200):
        peer.frame(serve(server))
    counts = server.physics.counts
    assert (counts.stepped, counts.resent, counts.lost, counts.restarts) == (200, 0, 0, 0)
    assert peer.frame_count == 200 and peer.log.sent == 200 and peer.log.unparsed == 0
    assert peer.log.clock == pytest.approx(200 / 400)                 # SITL's clock = physics time
    stamps = [fields['timestamp'] for fields in peer.log.parsed]
    assert np.allclose(np.diff(stamps), 1 / 400)
    fields = peer.log.parsed[-1]
    assert fields['accel_body'] == pytest.approx([0.0, 0.0, -GRAVITY])       # at rest, level
    assert set(fields) == {'timestamp', 'gyro', 'accel_body', 'position', 'quaternion', 'attitude', 'velocity'}


def test_a_lost_reply_is_answered_again_without_a_second_step(link):
    server, peer, _ = link
    for _ in range(3):
        peer.frame(serve(server))
    peer.send()
    server.poll(1.0)
    assert peer.receive(0.5) is not None            # the reply...
    peer.frame_count -= 1                           # ...as if it never arrived: SITL resends the frame
    peer.last_timestamp -= 1 / 400
    peer.log.clock -= 1 / 400
    fields = peer.frame(serve(server))
    counts = server.physics.counts
    assert (counts.stepped, counts.resent) == (4, 1)
    assert fields['timestamp'] == pytest.approx(4 / 400)
    assert peer.frame(serve(server))['timestamp'] == pytest.approx(5 / 400)


def test_silence_resends_pile_up_and_get_one_reply(link):
    server, peer, _ = link
    peer.frame(serve(server))
    for _ in range(4):                              # physics silent: SITL resends the same frame
        peer.send()
        assert peer.receive(0.05) is None
    replies = server.poll(1.0)
    assert [reply.kind for reply in replies] == ['new', 'resend', 'resend', 'resend']     # four copies queued
    assert peer.receive(0.5) is not None            # one answer
    assert peer.receive(0.05) is None               # no stale reply left behind
    for _ in range(5):
        peer.frame(serve(server))
    counts = server.physics.counts
    assert (counts.stepped, counts.resent, counts.lost) == (7, 3, 0)        # 4 copies: 1 stepped, 3 from the cache
    assert peer.log.clock == pytest.approx(7 / 400) and peer.log.repeated == 0


def test_two_frames_queued_get_one_answer(link):
    # SITL took a repeated reply as the answer to frame k + 1 and sent k + 2 without waiting:
    # both frames are stepped, only k + 2 is answered, and SITL is back in step.
    server, peer, _ = link
    peer.frame(serve(server))
    peer.send()
    peer.frame_count += 1
    peer.send()
    assert [reply.kind for reply in server.poll(1.0)] == ['new', 'new']
    fields = peer.receive(0.5)
    assert fields['timestamp'] == pytest.approx(3 / 400) and peer.receive(0.05) is None
    assert server.physics.counts.stepped == 3


def test_sitl_restart_resets_the_uav_and_keeps_the_time_axis(link):
    server, peer, logs = link
    peer.pwm[:4] = [1800] * 4                       # climb
    for _ in range(200):
        peer.frame(serve(server))
    assert server.physics.frame.position[2] > 0.5
    peer.restart()
    peer.pwm[:4] = [1000] * 4
    fields = peer.frame(serve(server))
    assert server.physics.counts.restarts == 1 and any('restarted' in line for line in logs)
    assert fields['position'] == pytest.approx([0.0, 0.0, 0.0]) and fields['velocity'] == pytest.approx([0.0] * 3)
    assert fields['timestamp'] == pytest.approx(201 / 400)          # physics time runs on
    for _ in range(10):
        peer.frame(serve(server))
    assert peer.frame_count == 11 and server.physics.counts.lost == 0


def test_32_channel_packets_and_garbage(link):
    server, peer, logs = link
    peer.close()
    peer32 = SitlJsonPeerDouble(server.port, channels=32, resend_after=0.05)
    try:
        peer32.sock.sendto(b'\x00garbage', ('127.0.0.1', server.port))
        assert server.poll(1.0) == []
        assert any('magic' in line for line in logs)
        for _ in range(5):
            peer32.frame(serve(server))
        assert server.physics.counts.stepped == 5 and server.physics.counts.rejected == 1
    finally:
        peer32.close()
        peer.sock = peer32.sock


def test_the_parser_double_reads_like_sitl():
    text = '{"timestamp":1.5,"imu":{"gyro":[1,2,3],"accel_body":[0,0,-9.8]},"position":[0,0,0],' \
           '"velocity":[1,1,1],"velocity_wind":[9,9,9],"attitude":[0,0,0]}'
    assert parse_sensors(text)['velocity'] == pytest.approx([1, 1, 1])
    # keys by substring: "velocity" is found inside "velocity_wind" when that comes first
    swapped = text.replace('"velocity":[1,1,1],"velocity_wind":[9,9,9]', '"velocity_wind":[9,9,9],"velocity":[1,1,1]')
    assert parse_sensors(swapped) is None
    assert parse_sensors(text.replace('"timestamp":1.5', '"timestamp" : 1.5'))['timestamp'] == 0.0
    assert parse_sensors(text.replace('"gyro":[1,2,3]', '"gyro": [1,2,3]')) is None
    assert parse_sensors(text.replace('"attitude":[0,0,0]', '"other":0')) is None       # no attitude at all


def test_the_tether_pulls_through_the_server():
    plant = TetherPlant(PlantConfig(initial_length=12.0, dt=0.01, uav=UavConfig(mode='prescribed')))
    tether = PlantTether(plant, resting_platform(), period=0.01)
    physics = JsonPhysics(JsonPhysicsConfig(start=(10.0, 0.0, 0.0)))
    physics.body[2] = 5.0                           # held up in the air, rotors off: it falls on its tether
    server = JsonPhysicsServer(physics, port=0, tether=tether, log=lambda line: None)
    peer = SitlJsonPeerDouble(server.port, resend_after=0.05)
    try:
        for _ in range(39):
            peer.frame(serve(server))
        held = tether.force().copy()                # the force the 40th frame holds
        peer.frame(serve(server))
        assert tether.outputs is not None and tether.outputs.t == pytest.approx(0.1)
        assert held[0] < -1.0 and held[2] < 0.0          # towards the boat, and down
        # rotors off: the accelerometer feels only the tether, f / m (world), read in the body
        specific_world = Rotation.from_quat(physics.frame.quaternion).apply(physics.frame.specific_force)
        assert specific_world == pytest.approx(held / physics.config.vehicle.mass, rel=1e-6, abs=1e-9)
    finally:
        peer.close()
        server.close()
