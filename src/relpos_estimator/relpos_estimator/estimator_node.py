"""ROS 2 node ``estimator``: the relative-altitude Kalman filter with the dGPS message logic.

A thin wrapper around :class:`relpos_estimator.estimator.Estimator`. It buffers
``/imu/reel``, ``/imu/uav`` (sensor_msgs/Imu) and ``/dgps/fix`` (tether_msgs/DgpsFix) by
their stamps and runs filter tick t once a reel IMU sample stamped t + ``input_delay`` or
later has arrived (the sensors publish a tick's fixes with its IMU samples, so by then
they are in), with the IMU samples stamped t (a missing or non-finite one is skipped and
flagged) and the fixes whose arrival stamp lies in (t - dt, t]. It publishes, stamped t:

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

from rclpy.node import Node
from sensor_msgs.msg import Imu
from tether_msgs.msg import DgpsFix
from tether_msgs.msg import FixRejection
from tether_msgs.msg import RelativeEstimate

from relpos_estimator.dgps import Fix
from relpos_estimator.estimator import Estimate
from relpos_estimator.estimator import Estimator
from relpos_estimator.estimator_params import PARAMETERS
from relpos_estimator.estimator_params import configs
from relpos_estimator.messages import fix_from_message
from relpos_estimator.messages import imu_vertical
from relpos_estimator.messages import stamp_ns
from relpos_estimator.sensors_node import SENSOR_INPUT
from relpos_estimator.sensors_node import to_stamp
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick


class EstimatorNode(Node):
    """Runs the estimator on the buffered sensor messages, by stamp."""

    def __init__(self) -> None:
        super().__init__('estimator')
        try:
            params = declare_parameters(self, PARAMETERS)
            covariances, logic = configs(params)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.estimator = Estimator(covariances, logic, params['rate'], 1.0 / params['dgps_rate'])
        self.period_ns = round(1e9 / params['rate'])
        self.delay_ns = round(params['input_delay'] * 1e9)
        self.reel: dict[int, float] = {}
        self.uav: dict[int, float] = {}
        self.fixes: list[Fix] = []
        self.next_ns: int | None = None
        self.newest_ns: int | None = None
        self.create_subscription(Imu, '/imu/reel', lambda m: self.on_imu(self.reel, m), SENSOR_INPUT)
        self.create_subscription(Imu, '/imu/uav', lambda m: self.on_imu(self.uav, m), SENSOR_INPUT)
        self.create_subscription(DgpsFix, '/dgps/fix', self.on_fix, SENSOR_INPUT)
        self.estimate_pub = self.create_publisher(RelativeEstimate, '/estimate/relative', STATE)
        self.foh_pub = self.create_publisher(RelativeEstimate, '/estimate/foh', STATE)
        self.rejection_pub = self.create_publisher(FixRejection, '/estimate/rejections', STATE)
        self.lockstep = Lockstep(self)
        self.lockstep.every(self.period_ns * 1e-9, self.on_tick)

    def on_imu(self, buffer: dict[int, float], msg: Imu) -> None:
        """Keep an IMU sample's vertical acceleration by stamp."""
        t_ns = stamp_ns(msg.header.stamp)
        buffer[t_ns] = imu_vertical(msg)
        if buffer is self.reel:
            self.newest_ns = t_ns if self.newest_ns is None else max(self.newest_ns, t_ns)
            self.filter(self.lockstep.clock_ns)

    def on_fix(self, msg: DgpsFix) -> None:
        """Keep a fix until the filter reaches its arrival stamp."""
        self.fixes.append(fix_from_message(msg))

    def on_tick(self, tick: Tick) -> None:
        """Filter up to the tick."""
        self.filter(tick.time_ns)

    def filter(self, until_ns: int) -> None:
        """Run every filter tick up to ``until_ns`` and the newest reel IMU stamp minus the input delay.

        Called at each lockstep tick and as reel IMU samples arrive (up to the latest ``/clock``),
        so that an estimate a consumer waits for by stamp comes once its samples are in.
        """
        if self.newest_ns is None:
            return
        if self.next_ns is None:
            self.next_ns = min(self.reel)
        target = min(self.newest_ns - self.delay_ns, until_ns)
        while self.next_ns <= target:
            t_ns = self.next_ns
            t = t_ns * 1e-9
            due = [f for f in self.fixes if f.arrival <= t + 1e-9]
            self.fixes = [f for f in self.fixes if f.arrival > t + 1e-9]
            estimate = self.estimator.step(t, self.reel.pop(t_ns, None), self.uav.pop(t_ns, None), due)
            self.publish(t_ns, estimate)
            self.next_ns += self.period_ns
            for buffer in (self.reel, self.uav):
                for key in [key for key in buffer if key < self.next_ns]:
                    del buffer[key]

    def publish(self, t_ns: int, est: Estimate) -> None:
        """Publish the estimate, the FOH baseline and the rejections of one tick."""
        stamp = to_stamp(t_ns * 1e-9)
        msg = RelativeEstimate()
        msg.header.stamp = stamp
        msg.header.frame_id = 'world'
        msg.dz, msg.dz_rate, msg.dz_accel, msg.accel_bias_reel, msg.accel_bias_uav = (float(v) for v in est.x)
        msg.covariance = [float(v) for v in est.P.ravel()]
        msg.horizontal.x, msg.horizontal.y = float(est.horizontal[0]), float(est.horizontal[1])
        msg.initialized = est.initialized
        msg.radial = est.radial
        if math.isfinite(est.horizontal_fix_time):
            msg.horizontal_fix_time = to_stamp(est.horizontal_fix_time)
        msg.nis = est.nis
        msg.rejected = est.rejected
        msg.rejection_reason = '; '.join(f'{r.reason}: {r.detail}' for r in est.rejections)
        self.estimate_pub.publish(msg)
        foh = RelativeEstimate()
        foh.header = msg.header
        foh.dz, foh.dz_rate = est.foh, est.foh_rate
        foh.dz_accel = foh.accel_bias_reel = foh.accel_bias_uav = math.nan
        foh.covariance = [math.nan] * 25
        foh.horizontal = msg.horizontal
        foh.initialized = math.isfinite(est.foh)
        foh.radial = msg.radial
        foh.horizontal_fix_time = msg.horizontal_fix_time
        foh.nis = math.nan
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
