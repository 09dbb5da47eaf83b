"""Test double: a MAVLink bridge whose ``/uav/set_mode`` takes a call and never answers it.

It publishes ``/uav/state`` (link up, position estimate ready, in STABILIZE) and ``/uav/pose``
(on the ground) at 10 Hz of wall time, and offers the bridge's four services; a call of
``/uav/set_mode`` writes ``called_file`` and then blocks for ever, as a bridge that hangs or
dies mid-call would (the test kills this process then). Spun on a multi-threaded executor so
the blocked call leaves the timer running.
"""

import sys
import threading
from pathlib import Path

from geometry_msgs.msg import PoseStamped
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from std_srvs.srv import SetBool
from std_srvs.srv import Trigger
from tether_msgs.msg import UavState
from tether_msgs.srv import SetMode
from tether_msgs.srv import Takeoff

from tether_common.node_main import run_node
from tether_common.qos import SENSOR
from tether_common.qos import STATE


class UavServicesDouble(Node):

    def __init__(self):
        super().__init__('mavlink_bridge')
        self.declare_parameter('called_file', '')
        self.called_file = Path(self.get_parameter('called_file').value)
        self.state_pub = self.create_publisher(UavState, '/uav/state', STATE)
        self.pose_pub = self.create_publisher(PoseStamped, '/uav/pose', SENSOR)
        group = ReentrantCallbackGroup()
        self.create_service(SetMode, '/uav/set_mode', self.hang, callback_group=group)
        for kind, name in ((SetBool, '/uav/arm'), (Takeoff, '/uav/takeoff'), (Trigger, '/uav/land')):
            self.create_service(kind, name, self.hang, callback_group=group)
        self.create_timer(0.1, self.publish, callback_group=group)

    def publish(self):
        state = UavState()
        state.header.stamp = self.get_clock().now().to_msg()
        state.connected, state.position_ready, state.mode = True, True, 'STABILIZE'
        self.state_pub.publish(state)
        pose = PoseStamped()
        pose.header.stamp, pose.header.frame_id = state.header.stamp, 'world'
        pose.pose.orientation.w = 1.0
        self.pose_pub.publish(pose)

    def hang(self, request, response):
        self.called_file.write_text('called\n')
        threading.Event().wait()
        return response


if __name__ == '__main__':
    sys.exit(run_node(UavServicesDouble, executor=MultiThreadedExecutor))
