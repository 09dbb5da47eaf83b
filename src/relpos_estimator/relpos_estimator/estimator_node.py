"""ROS 2 node ``estimator``: the relative-altitude Kalman filter with the dGPS message logic.

A thin wrapper around :class:`relpos_estimator.estimator.Estimator`, in lockstep
(:mod:`tether_common.lockstep`). ``/imu/reel`` and ``/imu/uav`` (sensor_msgs/Imu) are
declared inputs with the filter's period and the delay ``input_delay`` (one period: the
sensors node publishes the samples of t one tick later), so tick t runs the filter at
t - ``input_delay`` with the samples stamped then (a missing or non-finite one is skipped
and flagged). ``/dgps/fix`` (tether_msgs/DgpsFix) is not periodic: every fix received is
handed to the core, which considers it ``fix_hold`` after its arrival stamp (a fix that
reaches the node after that is logged; the core still fuses it at its time of fix). It
publishes, stamped with the filter's time:

* ``/estimate/relative`` (tether_msgs/RelativeEstimate, reliable) every tick,
* ``/estimate/foh`` (RelativeEstimate: dz and dz_rate of the first-order hold of the
  accepted fixes, the thesis's baseline) every tick,
* ``/estimate/rejections`` (tether_msgs/FixRejection, reliable), one per rejected fix.

The horizontal relative position and radial distance of the latest accepted fix pass
through in RelativeEstimate (``horizontal``, ``radial``, ``horizontal_fix_time``).
"""

from __future__ import annotations

import math
import sys

from builtin_interfaces.msg import Time as TimeMsg
from rclpy.node import Node
from sensor_msgs.msg import Imu
from tether_msgs.msg import DgpsFix
from tether_msgs.msg import FixRejection
from tether_msgs.msg import RelativeEstimate

from relpos_estimator.estimator import Estimate
from relpos_estimator.estimator import Estimator
from relpos_estimator.estimator_params import PARAMETERS
from relpos_estimator.estimator_params import configs
from relpos_estimator.messages import fix_from_message
from relpos_estimator.messages import imu_vertical
from relpos_estimator.messages import stamp_ns
from relpos_estimator.sensors_node import STATE_INPUT
from relpos_estimator.sensors_node import to_stamp
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import LOOP
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_models.dgps import Fix


class EstimatorNode(Node):
    """Runs the estimator on the buffered sensor messages, by stamp."""

    def __init__(self, **options) -> None:
        super().__init__('estimator', **options)
        try:
            params = declare_parameters(self, PARAMETERS)
            covariances, logic = configs(params)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.estimator = Estimator(covariances, logic, params['rate'], 1.0 / params['dgps_rate'])
        self.period = 1.0 / params['rate']
        self.delay_ns = round(params['input_delay'] * 1e9)
        self.started = False
        self.fixes: list[Fix] = []
        self.create_subscription(DgpsFix, '/dgps/fix', self.on_fix, STATE_INPUT)
        self.estimate_pub = self.create_publisher(RelativeEstimate, '/estimate/relative', LOOP)
        self.foh_pub = self.create_publisher(RelativeEstimate, '/estimate/foh', STATE)
        self.rejection_pub = self.create_publisher(FixRejection, '/estimate/rejections', STATE)
        # One message object per topic published every tick, refilled (publish() serialises it at once);
        # the FOH baseline's fields without a value are NaN once and for all
        self.estimate_msg = RelativeEstimate()
        self.estimate_msg.header.frame_id = 'world'
        self.foh_msg = RelativeEstimate()
        foh = self.foh_msg
        foh.dz_accel = foh.accel_bias_reel = foh.accel_bias_uav = math.nan
        foh.covariance = [math.nan] * 25
        foh.nis = math.nan
        self.lockstep = Lockstep(self)
        self.lockstep.every(self.period, self.on_tick, [
            Input('/imu/reel', Imu, self.period, params['input_delay']),
            Input('/imu/uav', Imu, self.period, params['input_delay'])])

    def on_fix(self, msg: DgpsFix) -> None:
        """Keep a fix for the next filter tick."""
        self.fixes.append(fix_from_message(msg))

    def on_tick(self, tick: Tick) -> None:
        """Run the filter at the tick's time minus the input delay, from the first reel IMU sample on."""
        t_ns = tick.time_ns - self.delay_ns
        samples = [tick.inputs[topic] for topic in ('/imu/reel', '/imu/uav')]
        reel, uav = (imu_vertical(m) if m is not None and stamp_ns(m.header.stamp) == t_ns else None
                     for m in samples)
        if not self.started and reel is None:
            return
        self.started = True
        t = t_ns * 1e-9
        hold = self.estimator.logic.fix_hold
        for fix in self.fixes:
            if fix.arrival + hold < t - self.period:
                self.get_logger().warning(f'fix {fix.sequence} (arrival {fix.arrival:.3f} s) reached the node at '
                                          f'{t:.2f} s, after its hold of {hold:g} s: fused at its time of fix')
        estimate = self.estimator.step(t, reel, uav, self.fixes)
        self.fixes = []
        self.publish(t_ns, estimate)

    def publish(self, t_ns: int, est: Estimate) -> None:
        """Publish the estimate, the FOH baseline and the rejections of one tick."""
        msg = self.estimate_msg
        msg.header.stamp = to_stamp(t_ns * 1e-9)
        msg.dz, msg.dz_rate, msg.dz_accel, msg.accel_bias_reel, msg.accel_bias_uav = est.x.ravel().tolist()
        msg.covariance = est.P.ravel().tolist()
        msg.horizontal.x, msg.horizontal.y = float(est.horizontal[0]), float(est.horizontal[1])
        msg.initialized = est.initialized
        msg.radial = est.radial
        msg.horizontal_fix_time = (to_stamp(est.horizontal_fix_time) if math.isfinite(est.horizontal_fix_time)
                                   else TimeMsg())
        msg.nis = est.nis
        msg.rejected = est.rejected
        msg.rejection_reason = '; '.join(f'{r.reason}: {r.detail}' for r in est.rejections)
        self.estimate_pub.publish(msg)
        foh = self.foh_msg
        foh.header = msg.header
        foh.dz, foh.dz_rate = est.foh, est.foh_rate
        foh.horizontal = msg.horizontal
        foh.initialized = math.isfinite(est.foh)
        foh.radial = msg.radial
        foh.horizontal_fix_time = msg.horizontal_fix_time
        self.foh_pub.publish(foh)
        for r in est.rejections:
            rej = FixRejection()
            rej.header.stamp = to_stamp(r.arrival)
            rej.header.frame_id = 'world'
            rej.fix_time = to_stamp(r.fix_time) if math.isfinite(r.fix_time) else rej.fix_time
            rej.sequence = r.sequence
            rej.reason = r.bit
            rej.reason_name = r.reason
            rej.detail = r.detail
            rej.dz = r.dz
            rej.innovation = r.innovation
            rej.nis = r.nis
            self.rejection_pub.publish(rej)


def main(args=None):
    """Run the estimator node."""
    sys.exit(run_node(EstimatorNode, args))


if __name__ == '__main__':
    main()
