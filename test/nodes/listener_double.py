"""Test double: a node under test that reacts to /test/estimate with /test/echo.

For each RelativeEstimate it publishes a geometry_msgs/PointStamped with the same stamp
and (dz, dz_rate, count of messages received), like an estimator or controller whose
outputs are recorded while it runs against a replayed bag.
"""

import sys

from geometry_msgs.msg import PointStamped
from rclpy.node import Node

from tether_common.node_main import run_node
from tether_common.qos import STATE
from tether_msgs.msg import RelativeEstimate


class ListenerDouble(Node):

    def __init__(self):
        super().__init__('test_listener')
        self.received = 0
        self.echo_pub = self.create_publisher(PointStamped, '/test/echo', STATE)
        self.create_subscription(RelativeEstimate, '/test/estimate', self.on_estimate, STATE)

    def on_estimate(self, estimate):
        self.received += 1
        echo = PointStamped()
        echo.header = estimate.header
        echo.point.x = estimate.dz
        echo.point.y = estimate.dz_rate
        echo.point.z = float(self.received)
        self.echo_pub.publish(echo)


if __name__ == '__main__':
    sys.exit(run_node(ListenerDouble))
