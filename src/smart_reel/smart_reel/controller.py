"""Length controllers of the smart reel (thesis Sec. 4.2, 4.3, 5.1).

Catenary-model controller (Fig. 4.2). Every 20 ms (50 Hz):

1. the reference length ``L_ref`` from the relative position, Δz every tick and the
   radial distance Δr as last sampled at 4 Hz (:class:`SampleHold`), through the project's
   one reference-length model (:func:`tether_dynamics.statics.reference_length.reference_length`,
   Eq. 4.4/4.5 with its blend and safeguards, or the exact heave-robust length), and at least
   the chord plus ``min_slack`` (model ``min_slack``): the model's slack over the chord shrinks
   with the range (5 cm at the pad, 1.5 m above the guide way), while the error of the relative
   position does not (the radial distance is the last dGPS fix's, held through a dropout:
   0.2 m off at the pad as the boat rolled, which reeled a 1.5 m tether 3 cm past taut and
   pulled 386 N on the landed UAV); 0: the model alone, as the thesis;
2. the gain-scheduled low-pass filter of Eq. 4.1 (:mod:`smart_reel.scheduler`);
3. the error ``e_k = L_k - L^LP_ref,k`` of the encoder's length against it;
4. a discrete PD on the motor voltage (:class:`DiscretePid` with ``ki = 0``, the thesis's
   controller): ``u_k = -(K_p e_k + K_d (e_k - e_{k-1})/T_s)``, positive paying out,
   clipped to the voltage limit. An optional integral term (``ki``) is frozen while the
   output saturates in the direction the error would drive it (conditional-integration
   anti-windup); the drive's current limit acts inside the motor model;
5. the voltage moves by at most ``R i_max`` (the winding resistance times the drive's
   current limit, 18 V with the defaults) per controller period from the voltage the drive
   applied last. A voltage step ``Δu`` on the turning motor first drives ``Δu/R`` through the
   winding, before the back-EMF follows the spool's new speed; within ``R i_max`` the drive
   stays off its current limit and the spool settles to the new speed within its
   mechanical time constant ``J R/(N K)²`` (about 3 ms), well inside the period. The
   thesis (Sec. 4.2) states no such limit; without it the tuned gain (``K_p`` ≈ 2900 V/m
   turns 1.6 cm of error into the full 48 V) reversed the drive at its current limit on
   every centimetre-sized step of the reference (the Kalman filter's corrections at each
   4 Hz dGPS fix, the 4 Hz radial distance), for longer than a period: the spool's
   acceleration torque at the limit, ``N K i_max/r`` ≈ 600 N, read as tether tension by the
   instantaneous estimate and tripped the reel-in limit (the estimate now takes the spool's
   acceleration out: :func:`smart_reel.sensors.tension_from_current`).

The gains are not guessed: ``tethersim reel tune`` (:mod:`smart_reel.tuning`) finds them.

Taut controller (Sec. 5.1, 6.1.4): a constant reel-in torque on the spool through the
drive's current loop, above the drivetrain's static friction so the spool keeps moving.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from smart_reel.scheduler import LowPass
from smart_reel.scheduler import SchmittScheduler
from tether_dynamics.statics.reference_length import reference_length


class SampleHold:
    """Holds a signal sampled on a fixed time grid (e.g. the 4 Hz radial distance)."""

    def __init__(self, period: float) -> None:
        self.period = period
        self.value: float | None = None
        self._next = 0.0

    def update(self, t: float, value: float) -> float:
        """Take ``value`` if ``t`` reached the next grid instant; return the held value."""
        if self.value is None or t >= self._next - 1e-9:
            self.value = value
            self._next = (math.floor(t / self.period + 1e-9) + 1) * self.period
        return self.value


@dataclass
class PidOutput:
    """One controller output (V) and its parts."""

    output: float
    p_term: float
    i_term: float
    d_term: float
    saturated: bool


class DiscretePid:
    """``u = -(kp e + ki Σ e T + kd Δe/T)`` clipped to ``±limit`` and ``±step_limit`` from the last output.

    Conditional-integration anti-windup: the integral is frozen while either limit holds the
    output against the direction the error would drive it.
    """

    def __init__(self, kp: float, kd: float, ki: float, period: float, limit: float,
                 step_limit: float = math.inf) -> None:
        if min(kp, kd, ki) < 0.0 or period <= 0.0 or limit <= 0.0 or not step_limit > 0.0:
            raise ValueError(f'PID needs kp, kd, ki >= 0, period > 0, limit > 0, step_limit > 0 (got {kp}, {kd}, '
                             f'{ki}, {period}, {limit}, {step_limit})')
        self.kp, self.kd, self.ki = kp, kd, ki
        self.period = period
        self.limit = limit
        self.step_limit = step_limit
        self.integral = 0.0
        self.output = 0.0
        """The last output (V); the next moves at most ``step_limit`` from it."""
        self._previous: float | None = None

    def step(self, error: float, applied: float | None = None) -> PidOutput:
        """One controller period with the error ``error``.

        ``applied`` is the output actually applied since the last period (default: the last
        output), e.g. 0 after a brake held the drive; the new output moves at most
        ``step_limit`` from it.
        """
        previous = error if self._previous is None else self._previous
        self._previous = error
        last = self.output if applied is None else applied
        low = max(-self.limit, last - self.step_limit)
        high = min(self.limit, last + self.step_limit)
        p = -self.kp * error
        d = -self.kd * (error - previous) / self.period
        i_candidate = self.integral - self.ki * error * self.period
        raw = p + d + i_candidate
        saturated = not low <= raw <= high
        if not saturated or raw * (i_candidate - self.integral) < 0.0:
            self.integral = i_candidate
        u = p + d + self.integral
        self.output = min(max(u, low), high)
        return PidOutput(self.output, p, self.integral, d, saturated)


@dataclass
class CatenaryOutput:
    """The catenary controller's command and internals for one tick."""

    voltage: float
    reference_length: float
    reference_model: str
    filtered_reference: float
    length_error: float
    alpha: float
    slow: bool
    pid: PidOutput


class CatenaryController:
    """Sec. 4.2: reference length, scheduled low-pass filter, PD on motor voltage."""

    def __init__(self, kp: float, kd: float, ki: float, period: float, voltage_limit: float,
                 reference_mode: str = 'poly', scheduler: SchmittScheduler | None = None,
                 voltage_step: float = math.inf, min_slack: float = 0.0) -> None:
        if reference_mode not in ('poly', 'exact'):
            raise ValueError(f"reference mode must be 'poly' or 'exact', got {reference_mode!r}")
        self.reference_mode = reference_mode
        self.min_slack = min_slack
        self.scheduler = scheduler or SchmittScheduler()
        self.filter = LowPass()
        self.pid = DiscretePid(kp, kd, ki, period, voltage_limit, voltage_step)

    def step(self, dr: float, dz: float, dz_rate: float, length: float,
             applied: float | None = None) -> CatenaryOutput:
        """One 50 Hz tick: relative position (m), vertical velocity (m/s), measured length (m).

        ``applied``: the voltage (V) the drive applied since the last tick, when it was not
        this controller's last output (0 after a brake); the new voltage moves at most
        ``voltage_step`` from it (step 5 of the module docstring).
        """
        ref = reference_length(dr, dz, self.reference_mode)
        floor = math.hypot(dr, dz) + self.min_slack
        reference, model = (ref.length, ref.model) if ref.length >= floor else (floor, 'min_slack')
        alpha = self.scheduler.update(dz_rate)
        filtered = self.filter.update(reference, alpha)  # Eq. 4.1
        error = length - filtered
        pid = self.pid.step(error, applied)
        return CatenaryOutput(pid.output, reference, model, filtered, error, alpha, self.scheduler.slow, pid)


class TautController:
    """Constant reel-in spool torque (N m) through the drive's current loop (Sec. 5.1)."""

    def __init__(self, torque: float, shaft_constant: float) -> None:
        if torque <= 0.0:
            raise ValueError(f'taut torque must be positive, got {torque}')
        self.torque = torque
        self.current = -torque / shaft_constant
