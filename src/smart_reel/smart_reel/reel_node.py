"""ROS 2 node ``reel``: the smart reel on sim time.

A thin wrapper around :class:`smart_reel.reel.ReelCore`. Every ``step`` of sim time, in
lockstep (:mod:`tether_common.lockstep`), it selects its inputs by stamp, the latest
messages stamped at or before ``t - input_delay`` (their producers' periods are
``tether_state_rate`` and ``relative_rate``), steps the core and publishes

* ``/reel/command`` (tether_msgs/ReelCommand, ``CONTROL_PAYOUT_RATE``) every step: the
  payout the reel's drive made over ``[t, t + step]``, for the plant to impose over the same
  interval (the plant's ``reel_drive: payout_rate``);
* ``/reel/state`` (tether_msgs/ReelState) and ``/reel/diagnostics``
  (tether_msgs/ReelControllerDiagnostics) at every controller tick (50 Hz).

Safety trips: while a trip holds the reel, ``/reel/state.mode`` is ``MODE_FAULT`` and
``/reel/diagnostics.safety_trip`` holds its reason; ``trip_count`` counts trips since the
start (a subscriber that missed a short trip sees the count rise), and each new trip is
logged with its reason (``/rosout``). A mission node aborts on these.

Inputs: ``/tether/state`` (tether_msgs/TetherState: tension at the guide way, departure
angle, clearances) and the relative position, ``/truth/relative``
(tether_msgs/RelativePosition, like the thesis's MoCap) or ``/estimate/relative``
(tether_msgs/RelativeEstimate) as ``relative_source`` says.

Loop delay: the tension acting on the drum over ``[t, t + step]`` is the plant's at
``t - input_delay`` (one plant step by default), and the plant applies the payout of
``[t, t + step]`` after receiving it; why the drive is integrated here and not in the
plant is in :mod:`smart_reel.winch`.
"""

from __future__ import annotations

import math
import sys
from typing import cast

from rclpy.node import Node
from tether_msgs.msg import ReelCommand
from tether_msgs.msg import ReelControllerDiagnostics
from tether_msgs.msg import ReelState
from tether_msgs.msg import RelativeEstimate
from tether_msgs.msg import RelativePosition
from tether_msgs.msg import TetherState

from smart_reel.reel import ReelCore
from smart_reel.reel import ReelInputs
from smart_reel.reel import ReelOutputs
from smart_reel.reel import build_core
from smart_reel.reel_params import PARAMETERS
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.lockstep import stamp_ns
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import LOOP
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters

MODES = {'catenary': ReelState.MODE_CATENARY, 'taut': ReelState.MODE_TAUT, 'locked': ReelState.MODE_LOCKED,
         'fault': ReelState.MODE_FAULT}


def relative_inputs(msg, inputs: ReelInputs) -> None:
    """Fill Δr, Δz, Δż from a RelativePosition or a RelativeEstimate (none from an estimate not yet initialized)."""
    if isinstance(msg, RelativePosition):
        inputs.dr = math.hypot(msg.position.x, msg.position.y)
        inputs.dz = msg.position.z
        inputs.dz_rate = msg.velocity.z
    elif msg.initialized and math.isfinite(msg.dz) and math.isfinite(msg.horizontal.x):
        inputs.dr = math.hypot(msg.horizontal.x, msg.horizontal.y)
        inputs.dz = msg.dz
        inputs.dz_rate = msg.dz_rate


class ReelNode(Node):
    """Runs the smart reel's drive, sensors, controller and safety against the plant."""

    def __init__(self, **options) -> None:
        super().__init__('reel', **options)
        try:
            self.params = declare_parameters(self, PARAMETERS)
            build_core(self.params, self.params['initial_length'] or 1.0)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        p = self.params
        self.core: ReelCore | None = None
        self._trips_logged = 0
        self.relative_topic, relative_type = (('/truth/relative', RelativePosition) if p['relative_source'] == 'truth'
                                              else ('/estimate/relative', RelativeEstimate))
        inputs = [Input('/tether/state', TetherState, 1.0 / p['tether_state_rate'], p['input_delay'], LOOP),
                  Input(self.relative_topic, relative_type, 1.0 / p['relative_rate'], p['input_delay'], LOOP)]
        self.command_pub = self.create_publisher(ReelCommand, '/reel/command', LOOP)
        self.state_pub = self.create_publisher(ReelState, '/reel/state', STATE)
        self.diagnostics_pub = self.create_publisher(ReelControllerDiagnostics, '/reel/diagnostics', STATE)
        self.lockstep = Lockstep(self)
        self.lockstep.every(p['step'], self.tick, inputs)
        self.get_logger().info(
            f'smart reel: {p["controller"]} controller, relative position from {p["relative_source"]}, '
            f'step {p["step"]:g} s, control {p["control_rate"]:g} Hz, kp {p["kp"]:g} V/m, kd {p["kd"]:g} V s/m')

    def _inputs(self, tick: Tick) -> tuple[ReelInputs, TetherState | None]:
        inputs = ReelInputs()
        state = tick.inputs['/tether/state']
        if state is not None:
            inputs.tension = state.tension_reel
            inputs.departure_angle = state.departure_angle
            inputs.clearance = min(state.clearance_deck + self.params['guide_height'], state.clearance_sea)
            inputs.plant_length = state.deployed_length
            inputs.plant_time = stamp_ns(state.header.stamp) * 1e-9
        relative = tick.inputs[self.relative_topic]
        if relative is not None:
            relative_inputs(relative, inputs)
        return inputs, state

    def tick(self, tick: Tick) -> None:
        """Step the reel over ``[t, t + step]`` and publish its command (and state at controller ticks)."""
        inputs, state = self._inputs(tick)
        if self.core is None:
            length = self.params['initial_length'] or (state.deployed_length if state is not None else 0.0)
            if length <= 0.0:
                return
            try:
                self.core = build_core(self.params, length)
            except ValueError as error:
                raise ConfigurationError(str(error)) from None
        out = self.core.step(tick.seconds, inputs)
        stamp = tick.stamp
        command = ReelCommand()
        command.header.stamp = stamp
        command.header.frame_id = 'reel'
        command.control = ReelCommand.CONTROL_PAYOUT_RATE
        command.mode = MODES[out.mode]
        command.motor_voltage = out.voltage
        command.spool_rate = out.mean_spool_rate
        command.spool_torque = out.shaft_torque
        command.payout_rate = out.command_payout
        self.command_pub.publish(command)
        if out.trips > self._trips_logged:
            self._trips_logged = out.trips
            self.get_logger().warning(f'safety trip {out.trips} at {tick.seconds:.2f} s: {out.trip}; the reel holds')
        if out.control_tick:
            self.state_pub.publish(self._state(stamp, out))
            self.diagnostics_pub.publish(self._diagnostics(stamp, out, inputs))

    @staticmethod
    def _state(stamp, out: ReelOutputs) -> ReelState:
        msg = ReelState()
        msg.header.stamp = stamp
        msg.header.frame_id = 'reel'
        msg.deployed_length = out.measured_length
        msg.spool_rate = out.spool_rate
        msg.payout_rate = out.payout_rate
        msg.motor_voltage = out.voltage
        msg.motor_current = out.current
        msg.motor_torque = out.shaft_torque
        msg.tension_estimate = out.tension_estimate
        msg.guide_arm_angle = out.arm_angle
        msg.mode = MODES[out.mode]
        msg.spool_angle = out.spool_angle
        msg.spool_radius = out.radius
        msg.current_limited = out.current_limited
        return msg

    def _diagnostics(self, stamp, out: ReelOutputs, inputs: ReelInputs) -> ReelControllerDiagnostics:
        msg = ReelControllerDiagnostics()
        msg.header.stamp = stamp
        msg.header.frame_id = 'reel'
        c = out.control
        if c is not None:
            msg.reference_model = c.reference_model
            msg.reference_length = c.reference_length
            msg.filtered_reference_length = c.filtered_reference
            msg.length_error = c.length_error
            msg.filter_alpha = c.alpha
            msg.scheduler_state = (ReelControllerDiagnostics.SCHEDULER_SLOW if c.slow
                                   else ReelControllerDiagnostics.SCHEDULER_FAST)
            msg.p_term, msg.d_term, msg.i_term = c.pid.p_term, c.pid.d_term, c.pid.i_term
            msg.voltage_saturated = c.pid.saturated
            msg.relative_radial = cast(ReelCore, self.core).radial.value
        else:
            msg.reference_length = msg.filtered_reference_length = msg.length_error = math.nan
            msg.relative_radial = math.nan
        msg.relative_height = inputs.dz if inputs.dz is not None else math.nan
        msg.relative_vertical_velocity = inputs.dz_rate if inputs.dz_rate is not None else math.nan
        msg.current_limited = out.current_limited
        msg.safety_trip = out.trip
        msg.trip_count = out.trips
        return msg


def main(args=None):
    """Run the reel node."""
    sys.exit(run_node(ReelNode, args))


if __name__ == '__main__':
    main()
