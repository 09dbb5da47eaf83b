"""Test double: publishes deterministic messages in lockstep and logs what it sent.

Publishes a custom type (tether_msgs/RelativeEstimate, reliable), a standard sensor type
(sensor_msgs/Imu, sensor-data QoS) and a latched tether_msgs/UavState. Every published
message is also written as one JSON line to ``sent_log``, so a test can compare the bag
with what was really published. ``crash_at`` > 0 makes the node die with status 3 at
that sim time (a crashing node for the failure-path tests), once the estimates it already
published are acknowledged: a burst of late ticks must not be lost in flight, since the
tests count what the bag kept of what was delivered before the crash.
"""

import json
import os
import sys

from rclpy.duration import Duration
from rclpy.node import Node
from sensor_msgs.msg import Imu

from tether_common.lockstep import Lockstep
from tether_common.node_main import run_node
from tether_common.qos import LATCHED
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_msgs.msg import RelativeEstimate
from tether_msgs.msg import UavState


class TalkerDouble(Node):

    def __init__(self):
        super().__init__('test_talker')
        self.declare_parameter('rate', 50.0)
        self.declare_parameter('sent_log', '')
        self.declare_parameter('crash_at', 0.0)
        self.count = 0
        self.crash_at = self.get_parameter('crash_at').value
        path = self.get_parameter('sent_log').value
        self.log = open(path, 'w') if path else None
        self.estimate_pub = self.create_publisher(RelativeEstimate, '/test/estimate', STATE)
        self.imu_pub = self.create_publisher(Imu, '/test/imu', SENSOR)
        self.state_pub = self.create_publisher(UavState, '/test/uav_state', LATCHED)
        state = UavState(connected=True, armed=False, ready=False, mode='GUIDED')
        self.state_pub.publish(state)
        self._record('/test/uav_state', {'mode': state.mode, 'connected': True})
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / self.get_parameter('rate').value, self.tick)

    def tick(self, tick):
        if self.crash_at > 0 and tick.time_ns >= self.crash_at * 1e9:
            print('talker_double: crashing on purpose', flush=True)
            self.estimate_pub.wait_for_all_acked(Duration(seconds=5))
            os._exit(3)
        self.count += 1
        estimate = RelativeEstimate()
        estimate.header.stamp = tick.stamp
        estimate.header.frame_id = 'world'
        estimate.dz = 10.0 + 0.001 * self.count
        estimate.dz_rate = -0.5 * self.count
        estimate.covariance = [float(i + self.count) for i in range(25)]
        estimate.rejected = self.count % 7
        estimate.rejection_reason = f'reason {self.count}'
        self.estimate_pub.publish(estimate)
        self._record('/test/estimate', {'stamp': tick.time_ns, 'dz': estimate.dz, 'dz_rate': estimate.dz_rate,
                                        'covariance': list(estimate.covariance), 'rejected': estimate.rejected,
                                        'rejection_reason': estimate.rejection_reason})
        imu = Imu()
        imu.header.stamp = tick.stamp
        imu.header.frame_id = 'boat'
        imu.linear_acceleration.z = 9.81 + 0.01 * self.count
        self.imu_pub.publish(imu)
        self._record('/test/imu', {'stamp': tick.time_ns, 'az': imu.linear_acceleration.z})

    def _record(self, topic, values):
        if self.log:
            self.log.write(json.dumps({'topic': topic, **values}) + '\n')
            self.log.flush()


if __name__ == '__main__':
    sys.exit(run_node(TalkerDouble))
