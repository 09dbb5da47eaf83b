"""Mission logic of the tethered UAV: take off, hold station over the boat, land (no rclpy).

The thesis's flights (Sec. 5.3, 5.4) hold the UAV at a relative position to the smart reel's
guide way: 5 m up and 2.5 m radial indoors, 30 m up and 15 m radial outdoors, near the
recommended ratio Δr/Δz ≈ 0.46 of the heave-robust reference model (Sec. 4.2). The station is
fixed in ``world`` (ENU, origin at the guide way's neutral position), so the UAV holds its
position while the boat heaves under it and the reel absorbs the motion.

:class:`MissionLogic` is stepped with the time and what the graph knows (:class:`Inputs`)
and returns what to do (:class:`Outputs`): at most one autopilot request at a time (mode,
arm, takeoff, land, with the answer of the previous one fed back) and the position setpoint.
Phases: ``wait`` (for the link and the autopilot's position estimate) → ``guided`` →
``arm`` → ``takeoff`` → ``climb`` → ``hold`` → ``return`` → ``land`` → ``landed``. At the
end time, with a ``return_speed``, a flying UAV returns over its pad on the boat before it
lands: the setpoint moves in a straight line from the station to over the pad at
``return_height`` (default: the hold altitude, as ArduCopter's RTL returns) at ``return_speed``
(so the reel, reeling in, keeps up), a function of the step's time alone; once the UAV is
within ``return_tolerance`` of the pad horizontally the mission lands, descending onto the
pad (``return_speed`` 0: it lands where it is). Returning down the line toward the guide way
keeps Δr/Δz away from 0, where the catenary reference (Sec. 4.2) is the straight chord: a
hanging tether all the way down.

A reel trip that counts (tension or fouling; :class:`TripMonitor`) aborts the mission, with
its reason kept as the outcome: a flying UAV returns over its pad at once and lands there
(with a ``return_speed``), or holds its station until the end (without one). It never lands
where it is: beside the boat, with the reel braked, that lays the tether on the deck or the
sea. The return brings the UAV toward the guide way, shortening the tether, which is what
either kind of trip calls for (the reel stops paying out a tether that sags toward the
deck, and stops reeling in one that pulls). A trip during the return or the landing does
not change them. :class:`TripMonitor` decides when a reel trip counts: once the reel has
stayed tripped for ``abort_after`` seconds (0: at once); the reel's own trips clear when
their condition does, so a trip shorter than that is the reel refusing one direction for a
while, and the mission flies on.

Losing the autopilot ends the mission in phase ``lost`` (:class:`AutopilotWatch`), with the
reason kept, and nothing is asked of the autopilot after it: from a flying phase (take-off to
landing) when the link stays down (closed or stale) for ``link_grace`` s, when the autopilot
rebooted (the bridge's reboot count grew), when it is disarmed while climbing, holding or
returning, or when it comes back from a gap in another mode than GUIDED; from any phase when a
request got no answer at all (the bridge answers every request within its own time-outs, so a
missing answer means the bridge is gone: nothing can be commanded). The mission does not take
off again: an autopilot that went silent or rebooted in flight left the UAV uncontrolled, so it
has fallen or landed wherever it was, its tether on the deck or in the sea, and after a reboot
ArduPilot needs its estimator again (~40 s) and may run other parameters. Flying it again is a
decision for the crew after looking at the UAV and the tether, not for the mission; the run
records why it ended (docs/autopilot-link.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

PHASES = ('wait', 'guided', 'arm', 'takeoff', 'climb', 'hold', 'return', 'land', 'landed', 'lost')
FLYING = ('takeoff', 'climb', 'hold')
"""Phases from which the end of the mission returns over the pad before landing."""
AIRBORNE = ('takeoff', 'climb', 'hold', 'return', 'land')
"""Phases in which the autopilot flies the UAV: losing it there ends the mission (:class:`AutopilotWatch`)."""
ENDED = ('landed', 'lost')
"""Phases after which the mission asks nothing more."""


@dataclass(frozen=True)
class MissionConfig:
    """Station and timing of a mission."""

    altitude: float = 30.0          # m, Δz of the station above the guide way's neutral position
    radial: float = 13.8            # m, Δr: horizontal distance of the station (0.46 x 30 m by default)
    bearing: float = 0.0            # rad, direction of the radial offset in world, from x (east) toward y
    land_time: float = math.inf     # s, time at which the mission lands
    climb_tolerance: float = 0.5    # m, take-off altitude reached within this
    retry_period: float = 2.0       # s, wait after a refused request before asking again
    pad: tuple = (0.0, 0.0)         # m, take-off pad on the boat, horizontal in world (the guide way: origin)
    return_speed: float = 0.0       # m/s, speed of the setpoint returning over the pad; 0: no return
    return_height: float | None = None   # m, height in world over the pad where the return ends; None: hold altitude
    return_tolerance: float = 0.5   # m, horizontal distance from over the pad at which the landing starts
    link_grace: float = 10.0        # s, a flying mission waits this long for a lost autopilot link before it ends

    def station(self) -> np.ndarray:
        """The station in world (ENU, m)."""
        return np.array([self.radial * math.cos(self.bearing), self.radial * math.sin(self.bearing), self.altitude])


@dataclass(frozen=True)
class Inputs:
    """What the mission knows at a step."""

    connected: bool = False         # autopilot link up and not stale
    position_ready: bool = False    # the autopilot's position estimate is in use
    armed: bool = False
    mode: str = ''
    position: np.ndarray | None = None    # m, UAV in world (ENU), None before the first pose
    reel_fault: str = ''            # reason of a reel trip (tension, fouling), '' when none
    busy: bool = False              # a request is still waiting for its answer
    answer: tuple[str, bool, str] | None = None   # (request kind, success, message) of the last answer
    reboots: int = 0                # autopilot reboots the bridge has seen since it started
    waiting_for: str = ''           # what the link waits for (the bridge's words), '' when nothing
    link_failure: str = ''          # why a request will never be answered, '' while the link answers


@dataclass(frozen=True)
class Outputs:
    """What the mission does at a step."""

    phase: str
    request: tuple[str, object] | None = None    # ('set_mode', 'GUIDED'), ('arm', True), ('takeoff', m), ('land', None)
    setpoint: np.ndarray | None = None           # m, world (ENU)
    reason: str = ''                              # why the mission lands, else the last refusal or wait


class TripMonitor:
    """Latches a reel trip that has lasted ``abort_after`` s (stamped reel states, in order).

    The smart reel's safety trips hold the reel while their condition lasts (tension while
    reeling in, clearance or departure angle while paying out). One that clears within a
    controller tick is the reel refusing one direction, and the mission may fly on; one that
    lasts means the reel cannot manage the tether, and the mission lands.
    """

    def __init__(self, abort_after: float = 0.0) -> None:
        self.abort_after = abort_after
        self.since: float | None = None
        self.fault = ''

    def update(self, t: float, tripped: bool, reason: str) -> str:
        """Feed the reel's state at ``t`` (s); return the latched trip reason, '' while none counts."""
        if self.fault:
            return self.fault
        if not tripped:
            self.since = None
            return ''
        if self.since is None:
            self.since = t
        if t - self.since >= self.abort_after:
            held = f' for {t - self.since:.2f} s' if self.abort_after > 0.0 else ''
            self.fault = f'{reason}{held}'
        return self.fault


class AutopilotWatch:
    """Decides when the autopilot is lost (see the module docstring); stepped with the mission's phase.

    The reboot count is taken as it is when the UAV leaves the ground phases, so a reboot
    before the take-off (SITL restarted while waiting) does not count; a link gap (closed or
    stale) counts once it has lasted ``grace`` s of the mission's time.
    """

    def __init__(self, grace: float = 10.0) -> None:
        self.grace = grace
        self.reboots: int | None = None
        self.since: float | None = None
        self.gap = False

    def update(self, t: float, phase: str, inputs: Inputs) -> str:
        """The reason the autopilot counts as lost at ``t`` (s) in ``phase``, '' while it does not."""
        if inputs.link_failure:
            return inputs.link_failure
        if phase not in AIRBORNE:
            self.reboots, self.since, self.gap = inputs.reboots, None, False
            return ''
        if self.reboots is None:
            self.reboots = inputs.reboots
        if inputs.reboots > self.reboots:
            return f'the autopilot rebooted in flight (reboot {inputs.reboots} of the link, seen at {t:.2f} s)'
        if not inputs.connected:
            if self.since is None:
                self.since = t
            if t - self.since >= self.grace:
                waiting = f' (waiting for {inputs.waiting_for})' if inputs.waiting_for else ''
                return f'link to the autopilot down for {t - self.since:.1f} s since {self.since:.2f} s{waiting}'
            return ''
        if self.since is not None:
            self.since, self.gap = None, True
        if phase in ('climb', 'hold', 'return'):
            if not inputs.armed:
                return f'the autopilot disarmed in flight (mode {inputs.mode or "unknown"}) at {t:.2f} s'
            if self.gap and inputs.mode != 'GUIDED':
                return f'the autopilot came back from a link gap in {inputs.mode or "no mode"}, not GUIDED, at {t:.2f} s'
        return ''


class MissionLogic:
    """The phase machine of one mission (see the module docstring)."""

    def __init__(self, config: MissionConfig) -> None:
        self.config = config
        self.station = config.station()
        self.phase = 'wait'
        self.reason = 'autopilot link and position estimate'
        self.aborted = False
        self.outcome = ''
        self.takeoff_altitude = 0.0
        self._next_request = -math.inf
        self._return_start: tuple[float, np.ndarray] | None = None    # (start time s, start setpoint m)
        self.watch = AutopilotWatch(config.link_grace)

    def step(self, t: float, inputs: Inputs) -> Outputs:
        """Advance to time ``t`` (s) with ``inputs``; return the request and setpoint to send."""
        if inputs.answer is not None and not inputs.answer[1]:
            self.reason = f'{inputs.answer[0]} refused: {inputs.answer[2]}'
            self._next_request = t + self.config.retry_period
        lost = '' if self.phase in ENDED else self.watch.update(t, self.phase, inputs)
        if lost:
            self.outcome = f'aborted: autopilot lost: {lost}'
            self.aborted = True
            self._enter('lost')
        if self.phase not in ('return', 'land', *ENDED):
            if inputs.reel_fault and not self.aborted:
                self.outcome = f'aborted: reel trip: {inputs.reel_fault}'
                self.aborted = True
                if self.phase not in FLYING:
                    self._enter('land')
                elif not self._start_return(t, inputs):
                    self._enter('hold', self.outcome)
            elif t >= self.config.land_time:
                self.outcome = self.outcome or 'end of the mission'
                if not (self.phase in FLYING and self._start_return(t, inputs)):
                    self._enter('land')
        if self.phase in AIRBORNE and not inputs.connected and self.watch.since is not None:
            # what the link says of the UAV is old or cleared: no request, no setpoint, the gap recorded
            return Outputs(self.phase, None, None, self.outcome or f'link to the autopilot down since {self.watch.since:.2f} s')
        handler = getattr(self, f'_{self.phase}')
        request, setpoint = handler(t, inputs)
        if request is not None:
            if inputs.busy or t < self._next_request:
                request = None
            else:
                self._next_request = t
        return Outputs(self.phase, request, setpoint, self.outcome or self.reason)

    def _start_return(self, t: float, inputs: Inputs) -> bool:
        """Start the return over the pad from the station (in hold) or the UAV's position at the station's
        altitude; False when the mission has no return (``return_speed`` 0) or no position yet.
        """
        if inputs.position is None or self.config.return_speed <= 0.0:
            return False
        start = self.station.copy() if self.phase == 'hold' else inputs.position.copy()
        start[2] = self.station[2]
        self._return_start = (t, start)
        self._enter('return')
        return True

    def _enter(self, phase: str, reason: str = '') -> None:
        self.phase = phase
        self.reason = reason
        self._next_request = -math.inf

    def _wait(self, t, inputs):
        if inputs.connected and inputs.position_ready and inputs.position is not None:
            self._enter('guided')
            return self._guided(t, inputs)
        return None, None

    def _guided(self, t, inputs):
        if inputs.mode == 'GUIDED':
            self._enter('arm')
            return self._arm(t, inputs)
        return ('set_mode', 'GUIDED'), None

    def _arm(self, t, inputs):
        if inputs.armed:
            self.takeoff_altitude = max(1.0, float(self.station[2] - inputs.position[2]))
            self._enter('takeoff')
            return self._takeoff(t, inputs)
        if inputs.mode != 'GUIDED':
            self._enter('guided', f'autopilot left GUIDED for {inputs.mode}')
            return self._guided(t, inputs)
        return ('arm', True), None

    def _takeoff(self, t, inputs):
        if inputs.answer is not None and inputs.answer[0] == 'takeoff' and inputs.answer[1]:
            self._enter('climb')
            return None, None
        if not inputs.armed:
            self._enter('arm', 'disarmed before take-off')
            return None, None
        return ('takeoff', self.takeoff_altitude), None

    def _climb(self, t, inputs):
        if inputs.position is not None and inputs.position[2] >= self.station[2] - self.config.climb_tolerance:
            self._enter('hold')
            return self._hold(t, inputs)
        return None, None

    def _hold(self, t, inputs):
        return None, self.station.copy()

    def return_setpoint(self, t: float) -> np.ndarray:
        """The return's setpoint at ``t`` (s): in a straight line from its start toward over the pad at
        ``return_height`` (default: the hold altitude), at ``return_speed``.
        """
        assert self._return_start is not None, 'the return has not started'
        t0, start = self._return_start
        height = start[2] if self.config.return_height is None else self.config.return_height
        target = np.array([self.config.pad[0], self.config.pad[1], height])
        distance = float(np.linalg.norm(target - start))
        travelled = min(distance, self.config.return_speed * max(0.0, t - t0))
        return target.copy() if travelled >= distance else start + (target - start) * (travelled / distance)

    def _return(self, t, inputs):
        setpoint = self.return_setpoint(t)
        pad = np.asarray(self.config.pad, dtype=float)
        over = (np.allclose(setpoint[:2], pad) and inputs.position is not None
                and float(np.linalg.norm(inputs.position[:2] - pad)) <= self.config.return_tolerance)
        if over:
            self._enter('land')
            return self._land(t, inputs)
        return None, setpoint

    def _land(self, t, inputs):
        if not inputs.armed:
            self._enter('landed')
            return None, None
        if inputs.mode == 'LAND':
            return None, None
        return ('land', None), None

    def _landed(self, t, inputs):
        return None, None

    def _lost(self, t, inputs):
        return None, None
