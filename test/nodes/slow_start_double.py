"""Test double: a node still being built when SIGTERM shuts rclpy down.

Once its node exists it writes ``started_file``, then keeps "building" until the context
has been shut down and makes one more rcl call (creating a publisher), as a node that
builds a large model at start-up does when it is stopped meanwhile.
"""

import sys
import time
from pathlib import Path

import rclpy
from rclpy.node import Node
from std_msgs.msg import Empty

from tether_common.node_main import run_node


class SlowStartDouble(Node):

    def __init__(self):
        super().__init__('slow_start')
        self.declare_parameter('started_file', '')
        Path(self.get_parameter('started_file').value).write_text('started\n')
        while rclpy.ok():
            time.sleep(0.01)
        self.create_publisher(Empty, '/test/built', 1)


if __name__ == '__main__':
    sys.exit(run_node(SlowStartDouble))
