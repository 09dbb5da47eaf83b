"""ArduCopter SITL (the real binary, ``--model JSON``) flies the tethered quad X of the JSON physics server.

SITL sends its motor outputs to :class:`uav_bridge.json_physics.server.JsonPhysicsServer`
and waits for each reply, so the physics sets the pace (SITL's ``--speedup`` only caps it)
and SITL's clock is the physics time. The MAVLink session of the bridge arms, takes off in
GUIDED and holds station while the plant's quasi-static tether, anchored on a resting boat,
pulls on the UAV. The physics and the session take turns in ticks of physics time
(:func:`uav_bridge.json_physics.flight.fly_and_hold`), so two flights at once, SITL capped at
different speed-ups, must give the same frames to the bit. Skipped only where no SITL binary
runs (see ``sitl_process.py``).

Measured over the hold (20 s of sim time; the scene's test holds 60 s): frames (none lost, none stepped twice), the mean
rotor thrust against weight plus the tether's pull (the vector |m g e_z - f|), and the
position-hold error about the take-off point.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from sitl_process import SitlProcess
from sitl_process import connect_when_listening
from sitl_process import sitl_unavailable
from tether_dynamics.plant import PlantConfig
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant import UavConfig
from tether_models.constants import GRAVITY
from uav_bridge.json_physics.flight import HoldPlan
from uav_bridge.json_physics.flight import fly_and_hold
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import JsonPhysicsConfig
from uav_bridge.json_physics.protocol import physics_port
from uav_bridge.json_physics.server import JsonPhysicsServer
from uav_bridge.json_physics.server import PlantTether
from uav_bridge.json_physics.server import resting_platform
from uav_bridge.mavlink.session import SessionConfig

UNAVAILABLE = sitl_unavailable()
pytestmark = [pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or ''), pytest.mark.long_run]

START = np.array([8.0, 0.0, 0.0])           # m, world: the UAV on the ground 8 m east of the boat
ALTITUDE = 12.0                             # m above the take-off point
TETHER_LENGTH = 16.0                        # m, guide way (0.5 m above the boat) to the UAV: it sags
HOLD = 20.0                                 # s of sim time (the scene's test holds 60 s)
SPEEDUPS = (100.0, 1.0)                     # SITL's caps on its pace: 1.0 holds one flight to real time
FRAME_RATE = 800                            # physics frames per s (ArduCopter arms above 1.8 x its 400 Hz loop)
JSON_PARAMETERS = (('FRAME_TYPE', 1), ('SIM_RATE_HZ', FRAME_RATE))          # quad X


def _fly(workdir, speedup: float) -> tuple:
    """One flight on its own SITL instance; its hold record, physics and log lines."""
    sitl = SitlProcess(workdir, speedup=speedup, model='JSON:127.0.0.1', parameters=JSON_PARAMETERS)
    plant = TetherPlant(PlantConfig(initial_length=TETHER_LENGTH, dt=0.01, uav=UavConfig(mode='prescribed')))
    tether = PlantTether(plant, resting_platform(), period=0.01)
    physics = JsonPhysics(JsonPhysicsConfig(start=tuple(START), frame_rate=FRAME_RATE))
    logs: list[str] = []
    server = JsonPhysicsServer(physics, physics_port(sitl.config.instance), tether=tether, log=logs.append)
    config = SessionConfig(url=sitl.url(), origin=tuple(START), link_timeout=5.0, reconnect_max=1.0,
                           stream_timeout=5.0, status_period=0.2, arm_timeout=300.0, command_timeout=60.0,
                           stream_rates={'ATTITUDE': 10.0, 'LOCAL_POSITION_NED': 10.0, 'HIGHRES_IMU': 10.0,
                                         'EKF_STATUS_REPORT': 2.0})
    try:
        return fly_and_hold(server, sitl, config, HoldPlan(altitude=ALTITUDE, hold=HOLD), log=logs.append), \
            physics, logs
    finally:
        sitl.close()
        server.close()
        print((workdir / 'sitl.log').read_text(errors='replace')[-2000:])


@pytest.fixture(scope='module')
def flights(tmp_path_factory):
    """The same flight twice at once, SITL capped at two different speed-ups, each on its own instance."""
    results: dict = {}
    # made here, not in the threads: the worker's first mktemp creates its base directory, and two at once race
    workdirs = {speedup: tmp_path_factory.mktemp(f'speedup{speedup:g}') for speedup in SPEEDUPS}

    def fly(speedup: float) -> None:
        try:
            results[speedup] = _fly(workdirs[speedup], speedup)
        except BaseException as error:     # noqa: BLE001 - raised in the test's thread below
            results[speedup] = error

    threads = [threading.Thread(target=fly, args=(speedup,)) for speedup in SPEEDUPS]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for result in results.values():
        if isinstance(result, BaseException):
            raise result
    return [results[speedup] for speedup in SPEEDUPS]


def test_arducopter_takes_off_and_holds_station_on_the_tether(flights):
    record, physics, logs = flights[0]
    # frames: every count SITL sent stepped exactly once, none skipped, none twice
    counts = record.frame_counts
    assert record.counts.lost == 0 and record.counts.restarts == 0 and record.counts.rejected == 0
    assert counts[0] == 0 and np.all(np.diff(counts) == 1) and record.counts.stepped == len(counts)
    assert record.sim_time == pytest.approx(len(counts) / FRAME_RATE)        # SITL's clock: the frames'
    # hover thrust balance: mean thrust against the mean of |m g e_z - f| (weight plus the tether's pull)
    mass = physics.config.vehicle.mass
    load = np.linalg.norm(np.array([0.0, 0.0, mass * GRAVITY]) - record.force, axis=1)
    balance = (record.thrust.mean() - load.mean()) / load.mean()
    pull = -record.force[:, 2].mean()
    error = record.position - record.target
    horizontal = np.linalg.norm(error[:, :2], axis=1)
    print(f'sim {record.sim_time:.1f} s in {record.wall_time:.0f} s wall; frames {len(counts)} '
          f'(resent {record.counts.resent}, lost {record.counts.lost}); climb {record.climb_time:.1f} s; '
          f'hold {record.t[-1] - record.t[0]:.1f} s: thrust {record.thrust.mean():.2f} N, weight {mass * GRAVITY:.2f} N '
          f'+ tether pull {pull:.2f} N down, {np.linalg.norm(record.force[:, :2], axis=1).mean():.2f} N sideways '
          f'-> |load| {load.mean():.2f} N, balance {100 * balance:+.2f} %; hold error: horizontal max '
          f'{horizontal.max():.3f} m, rms {np.sqrt(np.mean(horizontal ** 2)):.3f} m, vertical max '
          f'{np.abs(error[:, 2]).max():.3f} m')
    assert record.t[-1] - record.t[0] >= HOLD - 0.01
    assert pull > 1.0                                   # the tether hangs on the UAV
    assert abs(balance) < 0.01                          # within 1 % of weight plus tether pull
    assert horizontal.max() < 1.0 and np.abs(error[:, 2]).max() < 1.0
    assert not any('restarted' in line for line in logs)


def test_the_same_flight_at_two_speedups_at_once_is_the_same_to_the_bit(flights):
    (first, first_physics, _), (second, second_physics, _) = flights
    print(f'wall {first.wall_time:.0f} s and {second.wall_time:.0f} s for {first.sim_time:.2f} s of sim time; '
          f'frames {first_physics.counts} and {second_physics.counts}')
    if len(first.t) == len(second.t):
        apart = np.flatnonzero(np.any(first.position != second.position, axis=1))
        print(f'largest position difference {np.abs(first.position - second.position).max()} m; '
              f'first differing frame of the hold: {f"{first.t[apart[0]]:.5f} s" if len(apart) else "none"}')
    assert first.sim_time == second.sim_time and first.climb_time == second.climb_time
    assert np.array_equal(first.frame_counts, second.frame_counts)
    assert np.array_equal(first.t, second.t)
    assert np.array_equal(first.position, second.position)       # the UAV's track, every frame of the hold
    assert np.array_equal(first.thrust, second.thrust) and np.array_equal(first.force, second.force)


def test_a_sitl_restart_puts_the_uav_back_and_time_runs_on(tmp_path):
    sitl = SitlProcess(tmp_path, speedup=50.0, model='JSON:127.0.0.1', parameters=JSON_PARAMETERS)
    physics = JsonPhysics(JsonPhysicsConfig(start=tuple(START), frame_rate=FRAME_RATE))
    logs: list[str] = []
    server = JsonPhysicsServer(physics, physics_port(sitl.config.instance), log=logs.append)
    stop = threading.Event()

    def serve() -> None:
        while not stop.is_set():
            server.poll(0.1)

    thread = threading.Thread(target=serve, daemon=True)
    links = []
    try:
        thread.start()
        sitl.start()
        # SITL runs only once a MAVLink client is connected: a bare TCP connection will do
        links.append(connect_when_listening(sitl.config.port))
        _wait(lambda: physics.t > 3.0, 'SITL frames')
        sitl.kill()
        before, frames_before = physics.t, physics.counts.stepped
        sitl.start(wipe=False)
        links.append(connect_when_listening(sitl.config.port))
        _wait(lambda: physics.t > before + 3.0, 'frames of the restarted SITL')
        assert physics.counts.restarts == 1 and physics.counts.lost == 0 and physics.counts.rejected == 0
        assert any('SITL restarted' in line for line in logs)
        # one time axis through the restart: every frame stepped once, at the fixed rate
        assert physics.t == pytest.approx(physics.counts.stepped / FRAME_RATE)
        assert physics.counts.stepped > frames_before + 3 * FRAME_RATE
    finally:
        stop.set()
        thread.join(5)
        for link in links:
            link.close()
        sitl.close()
        server.close()


def _wait(predicate, what: str, timeout: float = 300.0) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'timed out waiting for {what}'
        time.sleep(0.05)
