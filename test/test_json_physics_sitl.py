"""ArduCopter SITL (the real binary, ``--model JSON``) flies the tethered quad X of the JSON physics server.

SITL sends its motor outputs to :class:`uav_bridge.json_physics_server.JsonPhysicsServer`
and waits for each reply, so the physics sets the pace (SITL's ``--speedup`` only caps it)
and SITL's clock is the physics time. The MAVLink session of the bridge arms, takes off in
GUIDED and holds station while the plant's quasi-static tether, anchored on a resting boat,
pulls on the UAV. Skipped only where no SITL binary runs (see ``sitl_process.py``).

Measured over the hold (60 s of sim time): frames (none lost, none stepped twice), the mean
rotor thrust against weight plus the tether's pull (the vector |m g e_z - f|), and the
position-hold error about the take-off point.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from sitl_process import SitlProcess
from sitl_process import sitl_unavailable
from test_uav_bridge_peer import Collector
from tether_common.constants import GRAVITY
from tether_dynamics.plant import PlantConfig
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant import UavConfig
from uav_bridge import telemetry
from uav_bridge.json_physics import JsonPhysics
from uav_bridge.json_physics import JsonPhysicsConfig
from uav_bridge.json_physics_server import JsonPhysicsServer
from uav_bridge.json_physics_server import PlantTether
from uav_bridge.json_physics_server import resting_platform
from uav_bridge.session import MavlinkSession
from uav_bridge.session import SessionConfig
from uav_bridge.sitl_json import physics_port

UNAVAILABLE = sitl_unavailable()
pytestmark = pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or '')

START = np.array([8.0, 0.0, 0.0])           # m, world: the UAV on the ground 8 m east of the boat
ALTITUDE = 12.0                             # m above the take-off point
TETHER_LENGTH = 16.0                        # m, guide way (0.5 m above the boat) to the UAV: it sags
HOLD = 60.0                                 # s of sim time
JSON_PARAMETERS = (('FRAME_TYPE', 1), ('SIM_RATE_HZ', 800))     # quad X; 800 frames per s (arming: > 1.8 x 400 Hz)
WALL_LIMIT = 900.0                          # s: a stuck run fails instead of hanging CI


class FlightRecord:
    """The physics server's loop in a thread, recording every stepped frame."""

    def __init__(self, server: JsonPhysicsServer, tether: PlantTether) -> None:
        self.server, self.tether = server, tether
        self.lock = threading.Lock()
        self.rows: list[tuple] = []                 # t, position (3), thrust, tether force (3)
        self.counts_seen: list[int] = []
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.wall_start = time.monotonic()

    def run(self) -> None:
        while not self.stop.is_set():
            for reply in self.server.poll(0.1):
                if reply.kind == 'resend':
                    continue
                frame = self.server.physics.frame
                with self.lock:
                    self.counts_seen.append(reply.packet.frame_count)
                    self.rows.append((frame.t, *frame.position, frame.thrusts.sum(), *self.tether.force()))

    def t(self) -> float:
        return self.server.physics.t

    def table(self, since: float) -> np.ndarray:
        with self.lock:
            rows = np.array(self.rows)
        return rows[rows[:, 0] >= since]


def wait_sim(record: FlightRecord, predicate, sim_timeout: float, what: str) -> None:
    """Wait until ``predicate()``, failing after ``sim_timeout`` s of physics time (or the wall limit)."""
    deadline, wall = record.t() + sim_timeout, time.monotonic() + WALL_LIMIT
    while not predicate():
        if record.t() > deadline or time.monotonic() > wall:
            pytest.fail(f'waiting for {what}: not after {record.t():.1f} s of sim time')
        time.sleep(0.05)


@pytest.fixture
def flight(tmp_path):
    sitl = SitlProcess(tmp_path, speedup=50.0, model='JSON:127.0.0.1', parameters=JSON_PARAMETERS)
    plant = TetherPlant(PlantConfig(initial_length=TETHER_LENGTH, dt=0.01, uav=UavConfig(mode='prescribed')))
    tether = PlantTether(plant, resting_platform(), period=0.01)
    physics = JsonPhysics(JsonPhysicsConfig(start=tuple(START)))
    logs: list[str] = []
    server = JsonPhysicsServer(physics, physics_port(sitl.config.instance), tether=tether, log=logs.append)
    record = FlightRecord(server, tether)
    collector = Collector()
    session = MavlinkSession(SessionConfig(url=sitl.url(), origin=tuple(START), link_timeout=5.0, reconnect_max=1.0,
                                           stream_timeout=5.0, status_period=0.2, arm_timeout=120.0,
                                           command_timeout=30.0,
                                           stream_rates={'ATTITUDE': 10.0, 'LOCAL_POSITION_NED': 10.0,
                                                         'HIGHRES_IMU': 10.0, 'EKF_STATUS_REPORT': 2.0}),
                             collector.on_sample, collector.on_status, collector.log)
    record.thread.start()
    sitl.start()
    session.start()
    try:
        yield sitl, session, collector, record, logs
    finally:
        session.stop()
        sitl.close()
        record.stop.set()
        record.thread.join(5)
        server.close()
        print((tmp_path / 'sitl.log').read_text(errors='replace')[-3000:])


def test_arducopter_takes_off_and_holds_station_on_the_tether(flight):
    sitl, session, collector, record, logs = flight
    status = collector.last_status
    wait_sim(record, lambda: status() is not None and status().connected, 30, 'HEARTBEAT')
    wait_sim(record, lambda: record.t() > 4.0, 30, 'the RC mode switch')     # SITL's RC sets STABILIZE at ~2.5 s
    assert session.set_mode('GUIDED').result(120).success
    wait_sim(record, lambda: status().position_ready, 120, 'the position estimate')
    armed = session.arm().result(300)
    assert armed.success, armed.message
    assert session.takeoff(ALTITUDE).result(120).success
    takeoff_t = record.t()

    def altitude() -> float:
        poses = collector.of(telemetry.Kinematics)
        return poses[-1].position[2] - START[2] if poses else -np.inf

    wait_sim(record, lambda: altitude() > ALTITUDE - 0.5, 60, f'take-off to {ALTITUDE} m')
    settle = record.t() + 5.0
    wait_sim(record, lambda: record.t() > settle + HOLD, HOLD + 10.0, f'{HOLD} s of hold')
    record.stop.set()                                   # SITL waits from here on: the counts stand still
    record.thread.join(5)
    hold = record.table(settle)
    climb_s = settle - 5.0 - takeoff_t

    # frames: every count SITL sent stepped exactly once, none skipped
    counts = np.array(record.counts_seen)
    physics_counts = record.server.physics.counts
    assert physics_counts.lost == 0 and physics_counts.restarts == 0 and physics_counts.rejected == 0
    assert np.all(np.diff(counts) == 1) and counts[0] == 0
    assert physics_counts.stepped == len(counts)

    # hover thrust balance: mean thrust against the mean of |m g e_z - f| (weight plus the tether's pull)
    mass = record.server.physics.config.vehicle.mass
    force = hold[:, 5:8]
    load = np.linalg.norm(np.array([0.0, 0.0, mass * GRAVITY]) - force, axis=1)
    thrust = hold[:, 4]
    balance = (thrust.mean() - load.mean()) / load.mean()
    pull = -force[:, 2].mean()
    target = START + [0.0, 0.0, ALTITUDE]
    error = hold[:, 1:4] - target
    horizontal = np.linalg.norm(error[:, :2], axis=1)
    print(f'sim {record.t():.1f} s in {time.monotonic() - record.wall_start:.0f} s wall; '
          f'frames {len(counts)} (resent {physics_counts.resent}, lost {physics_counts.lost}); '
          f'climb {climb_s:.1f} s; hold {hold[-1, 0] - hold[0, 0]:.1f} s: thrust {thrust.mean():.2f} N, '
          f'weight {mass * GRAVITY:.2f} N + tether pull {pull:.2f} N down, {-force[:, 0].mean():.2f} N to the boat '
          f'-> |load| {load.mean():.2f} N, balance {100 * balance:+.2f} %; hold error: horizontal max '
          f'{horizontal.max():.3f} m, rms {np.sqrt(np.mean(horizontal ** 2)):.3f} m, vertical max '
          f'{np.abs(error[:, 2]).max():.3f} m')
    assert pull > 1.0                                   # the tether hangs on the UAV
    assert abs(balance) < 0.01                          # within 1 % of weight plus tether pull
    assert horizontal.max() < 1.0 and np.abs(error[:, 2]).max() < 1.0
    assert not any('restarted' in line for line in logs)
