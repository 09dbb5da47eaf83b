"""The smart reel as one stepping object: ``ReelCore.step(t, inputs) -> ReelOutputs``.

Used unchanged by the reel node, the tuning procedure, the tests and replay. Each call
integrates the winch over ``[t, t + step]`` with the inputs the caller selected for tick
``t`` (the tether state and relative position stamped at or before ``t - input_delay``),
runs the controller on its own grid (50 Hz by default; the command is held in between)
and returns the command for the plant: the payout over the step it just integrated, to
be applied by the plant over the same interval. The loop reel → plant → reel therefore
carries ``input_delay`` (one plant step by default) plus the plant's own step: the
tension acting on the drum over ``[t, t + step]`` is the plant's tension at
``t - input_delay``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import replace

from smart_reel.controller import CatenaryController
from smart_reel.controller import CatenaryOutput
from smart_reel.controller import SampleHold
from smart_reel.controller import TautController
from smart_reel.motor import MotorParameters
from smart_reel.safety import SafetyLimits
from smart_reel.safety import SafetyMonitor
from smart_reel.scheduler import SchmittScheduler
from smart_reel.sensors import GuideArm
from smart_reel.sensors import tension_from_current
from smart_reel.spool import Encoder
from smart_reel.spool import SpoolGeometry
from smart_reel.tension_model import TetherStiffness
from smart_reel.winch import BRAKE
from smart_reel.winch import CURRENT
from smart_reel.winch import VOLTAGE
from smart_reel.winch import Friction
from smart_reel.winch import Winch
from smart_reel.winch import WinchState

CONTROLLERS = ('catenary', 'taut', 'locked')
HISTORY = 2000
"""Steps of the reel's own length kept to compare with the plant's (20 s at 10 ms)."""


@dataclass
class ReelInputs:
    """Inputs of one tick; ``None`` where nothing has arrived yet."""

    dr: float | None = None
    """m, relative radial distance UAV - guide way."""
    dz: float | None = None
    """m, relative height UAV - guide way."""
    dz_rate: float | None = None
    """m/s, relative vertical velocity."""
    tension: float | None = None
    """N, tether tension at the guide way."""
    departure_angle: float | None = None
    """rad, true departure angle above horizontal."""
    clearance: float = math.inf
    """m, lowest point above the deck or the water, whichever is closer."""
    plant_length: float | None = None
    """m, the plant's deployed length at ``plant_time``."""
    plant_time: float | None = None
    """s, stamp of ``plant_length``."""


@dataclass
class ReelOutputs:
    """Command, measured state and controller internals after one step."""

    mode: str
    drive: str
    drive_command: float
    voltage: float
    current: float
    shaft_torque: float
    spool_angle: float
    spool_rate: float
    mean_spool_rate: float
    payout_rate: float
    command_payout: float
    deployed_length: float
    measured_length: float
    radius: float
    tension_estimate: float
    arm_angle: float
    current_limited: bool
    trip: str
    trips: int
    control: CatenaryOutput | None
    control_tick: bool


def build_core(params: dict, initial_length: float) -> ReelCore:
    """A :class:`ReelCore` from the reel node's parameter values (:mod:`smart_reel.reel_params`)."""
    motor = MotorParameters(params['motor_resistance'], params['motor_inductance'], params['motor_torque_constant'],
                            params['motor_rotor_inertia'], params['motor_current_limit'], params['supply_voltage'],
                            params['gear_ratio'])
    spool = SpoolGeometry(params['core_radius'], params['drum_width'], params['tether_diameter'],
                          params['tether_capacity'], params['linear_density'])
    friction = Friction(params['friction_viscous'], params['friction_coulomb'], params['friction_static'])
    winch = Winch(motor, spool, friction, params['drum_inertia'], initial_length)
    limits = SafetyLimits(params['min_clearance'], math.radians(params['min_departure_angle']),
                          params['max_tension'], params['trip_delay'], math.radians(0.5 * params['arm_deadband']))
    return ReelCore(params['controller'], winch, Encoder(params['encoder_counts'], params['gear_ratio']),
                    GuideArm(math.radians(params['arm_deadband']), params['arm_encoder_bits']), limits,
                    step=params['step'], control_period=1.0 / params['control_rate'],
                    radial_period=1.0 / params['radial_rate'], kp=params['kp'], kd=params['kd'], ki=params['ki'],
                    voltage_limit=min(params['voltage_limit'], params['supply_voltage']),
                    reference_mode=params['reference_mode'],
                    scheduler=SchmittScheduler(params['schedule_upper'], params['schedule_lower'],
                                               params['alpha_slow']),
                    taut_torque=params['taut_torque'], min_slack=params['min_slack'], lead=params['lead'], sync_gain=params['sync_gain'],
                    stiffness=TetherStiffness(params['linear_density'], params['axial_stiffness']))


class ReelCore:
    """Winch, sensors, controller and safety of the smart reel, stepped with explicit time."""

    def __init__(self, controller: str, winch: Winch, encoder: Encoder, arm: GuideArm, limits: SafetyLimits, *,
                 step: float, control_period: float, radial_period: float, kp: float, kd: float, ki: float,
                 voltage_limit: float, reference_mode: str, scheduler: SchmittScheduler,
                 taut_torque: float, sync_gain: float = 10.0, stiffness: TetherStiffness | None = None,
                 min_slack: float = 0.0, lead: float = 0.0) -> None:
        if controller not in CONTROLLERS:
            raise ValueError(f'controller must be one of {CONTROLLERS}, got {controller!r}')
        ratio = control_period / step
        if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
            raise ValueError(f'the control period {control_period} s must be a whole number of steps of {step} s')
        self.mode = controller
        self.lead = lead
        self.winch = winch
        self.encoder = encoder
        self.arm = arm
        self.safety = SafetyMonitor(limits)
        self.step_size = step
        self.control_period = control_period
        self.radial = SampleHold(radial_period)
        self.catenary = CatenaryController(kp, kd, ki, control_period, voltage_limit, reference_mode, scheduler,
                                           voltage_step=winch.motor.voltage_step, min_slack=min_slack)
        self.taut = TautController(taut_torque, winch.motor.shaft_constant)
        self._next_control: float | None = None
        self._drive = BRAKE
        self._command = 0.0
        self._control: CatenaryOutput | None = None
        self._trip = ''
        self._arm_angle = math.nan
        self._tension = 0.0             # N, estimated over the last step
        self.sync_gain = sync_gain
        self.stiffness = stiffness
        self._history: dict[int, float] = {}
        self._corrections: dict[int, float] = {}

    def _sync(self, t: float, deployed: float, inputs: ReelInputs) -> float:
        """Payout (m/s) added to the command so that the plant's length converges onto the reel's.

        The plant's length at its stamp ``t_p`` has taken the commands stamped before
        ``t_p``; the corrections sent since are still on their way and are not repeated.
        """
        key = round(t / self.step_size)
        self._history[key + 1] = deployed  # the length at the end of this step
        for old in (key - HISTORY, key + 1 - HISTORY):
            self._history.pop(old, None)
            self._corrections.pop(old, None)
        correction = 0.0
        if inputs.plant_length is not None and inputs.plant_time is not None:
            seen = round(inputs.plant_time / self.step_size)
            own = self._history.get(seen)
            if own is not None:
                pending = sum(self._corrections.get(k, 0.0) for k in range(seen, key)) * self.step_size
                correction = self.sync_gain * (own - inputs.plant_length - pending)
        self._corrections[key] = correction
        return correction

    def _pull_slope(self, inputs: ReelInputs) -> tuple[float, float | None]:
        """``-∂T/∂L`` (N/m) of the tether at the plant's last step and the length it had there."""
        if (self.stiffness is None or inputs.tension is None or inputs.plant_length is None or inputs.dr is None
                or inputs.dz is None):
            return 0.0, None
        return self.stiffness(inputs.dr, inputs.dz, inputs.plant_length), inputs.plant_length

    def measured_length(self) -> float:
        """Deployed length (m) from the encoder count through the spool's layer model."""
        angle = self.encoder.angle(self.encoder.counts(self.winch.state.spool_angle))
        return self.winch.spool.deployed_length(self.winch.initial_length, angle)

    def _estimate_tension(self, before: WinchState, dt: float) -> float:
        """Tension (N) from the drive over the step just taken from ``before``
        (:func:`~smart_reel.sensors.tension_from_current`). On the brake, from the current alone
        (no current: zero), the brake having taken the spool's deceleration; over a step in which
        the spool reversed, started or stopped, the friction is not known (static, or Coulomb of
        either sign), so the estimate of the step before is kept.
        """
        w, s = self.winch, self.winch.state
        if self._drive != BRAKE and (before.spool_rate * s.spool_rate < 0.0
                                     or (before.spool_rate == 0.0) != (s.spool_rate == 0.0)):
            return self._tension
        speed_change = 0.0 if self._drive == BRAKE else s.spool_rate - before.spool_rate
        return tension_from_current((s.charge - before.charge) / dt, (s.spool_angle - before.spool_angle) / dt,
                                    speed_change, dt, w.spool.radius(w.deployed), w.motor.shaft_constant,
                                    w.inertia(), w.friction.viscous, w.friction.coulomb)

    def _control_tick(self, t: float, inputs: ReelInputs) -> None:
        length = self.measured_length()
        tension = self._tension
        self._control = None
        if self.mode == 'locked':
            drive, command, direction = BRAKE, 0.0, 0.0
        elif self.mode == 'taut':
            drive, command, direction = CURRENT, self.taut.current, -1.0
        elif inputs.dz is None or inputs.dr is None:
            drive, command, direction = BRAKE, 0.0, 0.0
        else:
            dr = self.radial.update(t, inputs.dr)
            applied = self._command if self._drive == VOLTAGE else 0.0
            dz = inputs.dz + self.lead * (inputs.dz_rate or 0.0)
            self._control = self.catenary.step(dr, dz, inputs.dz_rate or 0.0, length, applied)
            drive, command, direction = VOLTAGE, self._control.voltage, self._control.voltage
        self._trip = self.safety.check(t, direction, inputs.clearance, self._arm_angle, tension)
        if self._trip:
            drive, command = BRAKE, 0.0
        self._drive, self._command = drive, command

    def step(self, t: float, inputs: ReelInputs) -> ReelOutputs:
        """Run tick ``t`` (s): controller if due, then the winch over ``[t, t + step]``."""
        if self._next_control is None:  # the controller runs on multiples of its period
            self._next_control = math.ceil(t / self.control_period - 1e-9) * self.control_period
        tick = t >= self._next_control - 1e-9
        if tick:
            self._control_tick(t, inputs)
            self._next_control = (math.floor(t / self.control_period + 1e-9) + 1) * self.control_period
        w = self.winch
        before, before_length = replace(w.state), w.deployed
        state = w.step(self.step_size, self._drive, self._command, inputs.tension or 0.0, *self._pull_slope(inputs))
        payout = (w.deployed - before_length) / self.step_size
        self._tension = self._estimate_tension(before, self.step_size)
        command_payout = payout + self._sync(t, w.deployed, inputs)
        if inputs.departure_angle is not None:
            self._arm_angle = self.arm.read(inputs.departure_angle, payout)
        mode = 'fault' if self._trip else self.mode
        return ReelOutputs(
            mode=mode, drive=self._drive, drive_command=self._command, voltage=state.voltage,
            current=state.current, shaft_torque=w.motor.shaft_constant * state.current,
            spool_angle=state.spool_angle, spool_rate=state.spool_rate,
            mean_spool_rate=(state.spool_angle - before.spool_angle) / self.step_size, payout_rate=payout,
            command_payout=command_payout,
            deployed_length=w.deployed, measured_length=self.measured_length(), radius=w.spool.radius(w.deployed),
            tension_estimate=self._tension, arm_angle=self._arm_angle,
            current_limited=state.current_limited, trip=self._trip, trips=self.safety.trips,
            control=self._control if tick else None, control_tick=tick)
