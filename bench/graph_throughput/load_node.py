"""Benchmark load: a lockstep node standing in for the coming sensor, estimator and UAV nodes.

Every ``period`` it takes /platform/imu of its own tick (delay 0) and publishes ``topics``
sensor_msgs/Imu topics ``/bench/load_<name>_<k>`` carrying it with the tick's stamp, so
``bench/graph_throughput`` can add nodes and topics at the rates of the full graph.
"""

import sys

from rclpy.node import Node
from sensor_msgs.msg import Imu

from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.node_main import run_node
from tether_common.qos import SENSOR


class LoadNode(Node):

    def __init__(self):
        super().__init__('load')
        period = self.declare_parameter('period', 0.01).value
        imu_period = self.declare_parameter('imu_period', 0.01).value
        count = self.declare_parameter('topics', 3).value
        name = self.get_name()
        self.pubs = [self.create_publisher(Imu, f'/bench/{name}_{k}', SENSOR) for k in range(count)]
        self.lockstep = Lockstep(self)
        self.lockstep.every(period, self.tick, inputs=[Input('/platform/imu', Imu, imu_period, 0.0, SENSOR)])

    def tick(self, tick):
        imu = tick.inputs['/platform/imu']
        for publisher in self.pubs:
            msg = Imu() if imu is None else imu
            msg.header.stamp = tick.stamp
            publisher.publish(msg)


if __name__ == '__main__':
    sys.exit(run_node(LoadNode))
