"""Test double: a 1-D mass on a spring, stepped in lockstep, pushed by /test/command.

Every ``period`` it integrates x'' = (u - k x - c x') / m + w (semi-implicit Euler, w a
seeded random force per tick) and publishes /test/plant_state (geometry_msgs/PointStamped:
x = position in m, y = velocity in m/s, z = the random force drawn this tick). The force u
is /test/command's x, taken with a delay of one controller period: the closed loop's
explicit one-step delay (the controller reads the plant's state of its own tick).
"""

import sys

import numpy as np
from geometry_msgs.msg import PointStamped
from geometry_msgs.msg import Vector3Stamped
from rclpy.node import Node

from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.node_main import run_node
from tether_common.qos import STATE


class PlantDouble(Node):

    def __init__(self):
        super().__init__('test_plant')
        self.period = self.declare_parameter('period', 0.01).value
        controller_period = self.declare_parameter('controller_period', 0.02).value
        self.rng = np.random.default_rng(self.declare_parameter('seed', 1).value)
        self.x, self.v = 1.0, 0.0
        self.state_pub = self.create_publisher(PointStamped, '/test/plant_state', STATE)
        self.lockstep = Lockstep(self)
        self.lockstep.every(self.period, self.step, inputs=[
            Input('/test/command', Vector3Stamped, period=controller_period, delay=controller_period)])

    def step(self, tick):
        command = tick.inputs['/test/command']
        u = command.vector.x if command is not None else 0.0
        w = float(self.rng.normal(0.0, 0.5))
        self.v += self.period * (u - 4.0 * self.x - 0.2 * self.v + w)
        self.x += self.period * self.v
        msg = PointStamped()
        msg.header.stamp = tick.stamp
        msg.header.frame_id = 'world'
        msg.point.x, msg.point.y, msg.point.z = self.x, self.v, w
        self.state_pub.publish(msg)


if __name__ == '__main__':
    sys.exit(run_node(PlantDouble))
