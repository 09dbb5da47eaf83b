"""ArduCopter SITL flies the JSON physics in one process: arm, take off in GUIDED, hold (no rclpy).

For the real-autopilot test and the tether-model benchmark: the physics server answers SITL
in a thread of its own (recording every stepped frame), the MAVLink session
(:class:`uav_bridge.session.MavlinkSession`) flies the mission, and every wait is measured
in physics time (SITL runs only as fast as the physics replies), with a wall-time limit so a
stuck run fails instead of hanging. :func:`fly_and_hold` returns the frames of the hold.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from uav_bridge import telemetry
from uav_bridge.json_physics import FrameCounts
from uav_bridge.json_physics_server import JsonPhysicsServer
from uav_bridge.session import MavlinkSession
from uav_bridge.session import SessionConfig
from uav_bridge.sitl_runner import SitlRunner

RC_MODE_SWITCH = 4.0        # s of sim time: SITL's default RC input sets STABILIZE at ~2.5 s; GUIDED after it


class FlightError(RuntimeError):
    """The flight did not get where it should have; the message says where it stopped."""


@dataclass(frozen=True)
class HoldPlan:
    """Take off ``altitude`` m above the start and hold there ``hold`` s after ``settle`` s."""

    altitude: float
    hold: float = 60.0              # s of sim time
    settle: float = 5.0             # s after reaching the altitude before the hold counts
    ready_timeout: float = 150.0    # s of sim time for the EKF to use GPS
    climb_timeout: float = 90.0     # s of sim time for the climb
    wall_limit: float = 1800.0      # s of wall time for the whole flight


@dataclass(frozen=True)
class HoldRecord:
    """The stepped frames of the hold (physics time order) and the frame accounting of the run."""

    t: np.ndarray                   # s
    position: np.ndarray            # (n, 3) m, centre of mass, world
    thrust: np.ndarray              # (n,) N, sum of the rotors
    force: np.ndarray               # (n, 3) N, the tether's force on the UAV held over the frame, world
    frame_counts: np.ndarray        # every frame_count stepped in the run, in order
    counts: FrameCounts
    climb_time: float               # s from the take-off command to the altitude
    target: np.ndarray              # m, the hold point (start + altitude), world
    sim_time: float                 # s of physics time of the run
    wall_time: float                # s


class _Recorder:
    def __init__(self, server: JsonPhysicsServer) -> None:
        self.server = server
        self.lock = threading.Lock()
        self.rows: list[tuple] = []
        self.frame_counts: list[int] = []
        self.error: BaseException | None = None
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)

    def run(self) -> None:
        try:
            while not self.stop.is_set():
                for reply in self.server.poll(0.1):
                    if reply.kind == 'resend':
                        continue
                    frame = reply.frame
                    with self.lock:
                        self.frame_counts.append(reply.packet.frame_count)
                        self.rows.append((frame.t, *frame.position, frame.thrusts.sum(), *reply.force))
        except BaseException as error:      # noqa: BLE001 - reported by the flight's thread
            self.error = error


def fly_and_hold(server: JsonPhysicsServer, sitl: SitlRunner, session_config: SessionConfig, plan: HoldPlan,
                 log: Callable[[str], None] = print) -> HoldRecord:
    """Start SITL and the session, fly ``plan``, return the hold; SITL and the session are stopped after."""
    recorder = _Recorder(server)
    statuses: list = []
    poses: list = []

    def on_sample(sample, stamp) -> None:
        if isinstance(sample, telemetry.Kinematics):
            poses.append(sample)

    session = MavlinkSession(session_config, on_sample, statuses.append, lambda level, text: log(text))
    wall_start = time.monotonic()
    physics = server.physics

    def wait(predicate, sim_timeout: float, what: str) -> None:
        deadline = physics.t + sim_timeout
        while not predicate():
            if recorder.error is not None:
                raise FlightError(f'the physics server failed: {recorder.error}')
            if physics.t > deadline or time.monotonic() - wall_start > plan.wall_limit:
                raise FlightError(f'waiting for {what}: not after {physics.t:.1f} s of sim time')
            time.sleep(0.05)

    start = physics.frame.position.copy()
    recorder.thread.start()
    sitl.start()
    session.start()
    try:
        wait(lambda: bool(statuses) and statuses[-1].connected, 30.0, 'the HEARTBEAT')
        wait(lambda: physics.t > RC_MODE_SWITCH, 30.0, 'the RC mode switch')
        _command(session.set_mode('GUIDED'), 'GUIDED')
        wait(lambda: statuses[-1].position_ready, plan.ready_timeout, 'the position estimate')
        _command(session.arm(), 'arming')
        _command(session.takeoff(plan.altitude), 'take-off')
        takeoff_t = physics.t
        wait(lambda: bool(poses) and poses[-1].position[2] - start[2] > plan.altitude - 0.5, plan.climb_timeout,
             f'the climb to {plan.altitude} m')
        climb_time = physics.t - takeoff_t
        hold_from = physics.t + plan.settle
        wait(lambda: physics.t > hold_from + plan.hold, plan.settle + plan.hold + 10.0, f'{plan.hold} s of hold')
    finally:
        recorder.stop.set()
        recorder.thread.join(5)
        session.stop()
        sitl.stop()
    with recorder.lock:
        rows = np.array(recorder.rows)
        frame_counts = np.array(recorder.frame_counts)
    hold = rows[rows[:, 0] >= hold_from]
    return HoldRecord(t=hold[:, 0], position=hold[:, 1:4], thrust=hold[:, 4], force=hold[:, 5:8],
                      frame_counts=frame_counts, counts=physics.counts, climb_time=climb_time,
                      target=start + [0.0, 0.0, plan.altitude], sim_time=physics.t,
                      wall_time=time.monotonic() - wall_start)


def _command(future, what: str) -> None:
    result = future.result(600)
    if not result.success:
        raise FlightError(f'{what} refused: {result.message}')
