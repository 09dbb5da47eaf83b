"""Test double: a node under test that reacts to /test/estimate with /test/echo, in lockstep.

Every ``period`` it takes the latest RelativeEstimate with stamp <= its tick (waiting for
it: the talker's period is ``estimate_period``) and publishes a geometry_msgs/PointStamped
with the tick's stamp and (dz, dz_rate, number of ticks so far), like an estimator or
controller whose outputs are recorded while it runs against a replayed bag. Before the
first estimate it publishes nothing.
"""

import sys

from geometry_msgs.msg import PointStamped
from rclpy.node import Node

from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.node_main import run_node
from tether_common.qos import STATE
from tether_msgs.msg import RelativeEstimate


class ListenerDouble(Node):

    def __init__(self):
        super().__init__('test_listener')
        period = self.declare_parameter('period', 0.02).value
        estimate_period = self.declare_parameter('estimate_period', 0.02).value
        self.ticks = 0
        self.echo_pub = self.create_publisher(PointStamped, '/test/echo', STATE)
        self.lockstep = Lockstep(self)
        self.lockstep.every(period, self.on_tick, inputs=[
            Input('/test/estimate', RelativeEstimate, period=estimate_period)])

    def on_tick(self, tick):
        self.ticks += 1
        estimate = tick.inputs['/test/estimate']
        if estimate is None:
            return
        echo = PointStamped()
        echo.header.stamp = tick.stamp
        echo.header.frame_id = estimate.header.frame_id
        echo.point.x = estimate.dz
        echo.point.y = estimate.dz_rate
        echo.point.z = float(self.ticks)
        self.echo_pub.publish(echo)


if __name__ == '__main__':
    sys.exit(run_node(ListenerDouble))
