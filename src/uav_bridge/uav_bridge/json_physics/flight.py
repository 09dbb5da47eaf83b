"""ArduCopter SITL flies the JSON physics in one process: arm, take off in GUIDED, hold (no rclpy).

For the real-autopilot test and the tether-model benchmark: the physics server and the
MAVLink session (:class:`uav_bridge.mavlink.session.MavlinkSession`, stepped) take turns in ticks of
physics time, as the JSON physics and the bridge nodes do in the graph's lockstep, so the
flight is the same at any pace (SITL runs only as fast as the physics replies and reads the
session's bytes at a fixed frame); every wait is measured in physics time, with a wall-time
limit so a stuck run fails instead of hanging. :func:`fly_and_hold` returns the frames of
the hold.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass

import numpy as np

from uav_bridge.json_physics.model import FrameCounts
from uav_bridge.json_physics.server import JsonPhysicsServer
from uav_bridge.mavlink import telemetry
from uav_bridge.mavlink.session import MavlinkSession
from uav_bridge.mavlink.session import SessionConfig
from uav_bridge.sitl.runner import SitlRunner

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


class _SteppedFlight:
    """The physics and the session taking turns in ticks of physics time, as the graph's nodes do.

    A tick answers SITL's frames up to its time, waits for SITL's next servo packet (SITL then
    waits too) and only then lets the session read, time and send (:meth:`MavlinkSession.poll`
    at the tick's time): every MAVLink byte reaches SITL at the same frame at any pace.
    """

    def __init__(self, server: JsonPhysicsServer, tick: float, wall_limit: float) -> None:
        self.server = server
        self.physics = server.physics
        self.session: MavlinkSession | None = None
        self.tick_ns = round(tick * 1e9)
        self.time_ns = self.physics.time_ns
        self.rows: list[tuple] = []
        self.frame_counts: list[int] = []
        self.wall_start = time.monotonic()
        self.wall_limit = wall_limit

    @property
    def seconds(self) -> float:
        """The tick's time, s."""
        return self.time_ns * 1e-9

    def step(self) -> None:
        self.time_ns += self.tick_ns
        while True:
            if time.monotonic() - self.wall_start > self.wall_limit:
                raise FlightError(f'the flight took over {self.wall_limit:g} s of wall time, at '
                                  f'{self.physics.t:.1f} s of sim time')
            if self.physics.time_ns < self.time_ns:
                self._record(self.server.poll(0.5))
            elif self.server.waiting(0.5):
                break
        self.session.poll(self.seconds)

    def _record(self, replies) -> None:
        for reply in replies:
            if reply.kind == 'resend':
                continue
            frame = reply.frame
            self.frame_counts.append(reply.packet.frame_count)
            self.rows.append((frame.t, *frame.position, frame.thrusts.sum(), *reply.force))

    def until(self, predicate, sim_timeout: float, what: str) -> None:
        deadline = self.physics.t + sim_timeout
        while not predicate():
            if self.physics.t > deadline:
                raise FlightError(f'waiting for {what}: not after {self.physics.t:.1f} s of sim time')
            self.step()

    def command(self, future: Future, what: str) -> None:
        self.until(future.done, 600.0, what)
        result = future.result()
        if not result.success:
            raise FlightError(f'{what} refused: {result.message}')


def fly_and_hold(server: JsonPhysicsServer, sitl: SitlRunner, session_config: SessionConfig, plan: HoldPlan,
                 log: Callable[[str], None] = print, tick: float = 0.01) -> HoldRecord:
    """Start SITL and the session, fly ``plan`` in ticks of ``tick`` s, return the hold; SITL and
    the session are stopped after. The session's times (``session_config``) are sim time.
    """
    statuses: list = []
    poses: list = []

    def on_sample(sample, stamp) -> None:
        if isinstance(sample, telemetry.Kinematics):
            poses.append(sample)

    flight = _SteppedFlight(server, tick, plan.wall_limit)
    session = MavlinkSession(session_config, on_sample, statuses.append, lambda level, text: log(text),
                             clock=lambda: flight.seconds, stamp_clock=lambda: flight.seconds)
    flight.session = session
    physics = server.physics
    start = physics.frame.position.copy()
    server.warm_up()
    sitl.start()
    session.start(stepped=True)
    try:
        flight.until(lambda: bool(statuses) and statuses[-1].connected, 30.0, 'the HEARTBEAT')
        flight.until(lambda: physics.t > RC_MODE_SWITCH, 30.0, 'the RC mode switch')
        flight.command(session.set_mode('GUIDED'), 'GUIDED')
        flight.until(lambda: statuses[-1].position_ready, plan.ready_timeout, 'the position estimate')
        flight.command(session.arm(), 'arming')
        flight.command(session.takeoff(plan.altitude), 'take-off')
        takeoff_t = physics.t
        flight.until(lambda: bool(poses) and poses[-1].position[2] - start[2] > plan.altitude - 0.5,
                     plan.climb_timeout, f'the climb to {plan.altitude} m')
        climb_time = physics.t - takeoff_t
        hold_from = physics.t + plan.settle
        flight.until(lambda: physics.t > hold_from + plan.hold, plan.settle + plan.hold + 10.0,
                     f'{plan.hold} s of hold')
    finally:
        session.stop()
        sitl.stop()
    rows = np.array(flight.rows)
    hold = rows[rows[:, 0] >= hold_from]
    return HoldRecord(t=hold[:, 0], position=hold[:, 1:4], thrust=hold[:, 4], force=hold[:, 5:8],
                      frame_counts=np.array(flight.frame_counts), counts=physics.counts, climb_time=climb_time,
                      target=start + [0.0, 0.0, plan.altitude], sim_time=physics.t,
                      wall_time=time.monotonic() - flight.wall_start)
