"""Test double: a PD controller driving the plant double to x = 0, in lockstep.

Every ``period`` it reads /test/plant_state of its own tick (delay 0: it waits for the
plant's message of the same stamp) and publishes /test/command (geometry_msgs/
Vector3Stamped: x = force in N, y = the seeded measurement noise drawn this tick, z = the
stamp of the state it used, s).
"""

import sys

import numpy as np
from geometry_msgs.msg import PointStamped
from geometry_msgs.msg import Vector3Stamped
from rclpy.node import Node

from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import stamp_ns
from tether_common.node_main import run_node
from tether_common.qos import COMMAND


class ControllerDouble(Node):

    def __init__(self):
        super().__init__('test_controller')
        period = self.declare_parameter('period', 0.02).value
        plant_period = self.declare_parameter('plant_period', 0.01).value
        self.rng = np.random.default_rng(self.declare_parameter('seed', 2).value)
        self.command_pub = self.create_publisher(Vector3Stamped, '/test/command', COMMAND)
        self.lockstep = Lockstep(self)
        self.lockstep.every(period, self.step, inputs=[
            Input('/test/plant_state', PointStamped, period=plant_period, delay=0.0)])

    def step(self, tick):
        state = tick.inputs['/test/plant_state']
        noise = float(self.rng.normal(0.0, 0.01))
        msg = Vector3Stamped()
        msg.header.stamp = tick.stamp
        msg.header.frame_id = 'world'
        msg.vector.x = -20.0 * (state.point.x + noise) - 6.0 * state.point.y
        msg.vector.y = noise
        msg.vector.z = stamp_ns(state.header.stamp) * 1e-9
        self.command_pub.publish(msg)


if __name__ == '__main__':
    sys.exit(run_node(ControllerDouble))
