"""A node whose destruction hangs ends anyway: the shutdown watchdog of ``node_main.run_nodes``."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap

NODE = textwrap.dedent('''
    import sys, time
    from rclpy.node import Node
    from tether_common import node_main

    node_main.SHUTDOWN_TIMEOUT = 1.0

    class HangingNode(Node):
        """A test double whose destruction never returns, as a participant stuck in Fast DDS."""

        def __init__(self):
            super().__init__('hanging_double')
            self.timer = self.create_timer(0.05, self.spinning)

        def spinning(self):
            # From the executor: the node is built and in the list run_nodes destroys, so SIGINT now
            # reaches the destruction (sent while the constructor ran, it ended the build instead).
            self.timer.cancel()
            print('spinning', flush=True)

        def destroy_node(self):
            time.sleep(120.0)

    sys.exit(node_main.run_node(HangingNode))
''')


def test_a_node_stuck_in_its_destruction_is_ended_by_the_watchdog_with_status_1(ros_domain):
    process = subprocess.Popen([sys.executable, '-c', NODE], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    try:
        assert process.stdout.readline().strip() == 'spinning'
        process.send_signal(signal.SIGINT)
        _, stderr = process.communicate(timeout=60)      # the destruction alone would take 120 s
        assert process.returncode == 1
        assert 'Timeout' in stderr and 'destroy_node' in stderr    # faulthandler's dump names where it hung
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
