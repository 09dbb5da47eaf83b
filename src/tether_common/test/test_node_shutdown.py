"""A node whose spin or destruction hangs ends anyway: the shutdown watchdog of ``node_main.run_nodes``."""

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


def _signal_once_ready(args: list[str], ready: str, signum: int, timeout: float, **popen) -> tuple[int, str]:
    """Run ``python -c ARGS``, send ``signum`` once it prints ``ready``; return its exit status and standard error.

    A process still running after ``timeout`` (or a failed assertion) is killed, so none is left behind.
    """
    process = subprocess.Popen([sys.executable, '-c', *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, **popen)
    try:
        assert process.stdout.readline().strip() == ready
        process.send_signal(signum)
        _, stderr = process.communicate(timeout=timeout)
        return process.returncode, stderr
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_a_node_stuck_in_its_destruction_is_ended_by_the_watchdog_with_status_1(ros_domain):
    status, stderr = _signal_once_ready([NODE], 'spinning', signal.SIGINT, timeout=60)  # the destruction: 120 s
    assert status == 1
    assert 'Timeout' in stderr and 'destroy_node' in stderr    # faulthandler's dump names where it hung


STUCK_NODE = textwrap.dedent('''
    import sys, threading
    from rclpy.node import Node
    from tether_common import node_main

    node_main.SHUTDOWN_TIMEOUT = float(sys.argv[1])

    class StuckDouble(Node):
        """A test double whose callback never returns, waiting with the GIL released as a stuck executor does."""

        def __init__(self):
            super().__init__('stuck_double')
            self.timer = self.create_timer(0.05, self.stuck)

        def stuck(self):
            self.timer.cancel()
            held = threading.Lock()
            held.acquire()
            print('stuck', flush=True)
            held.acquire()

    sys.exit(node_main.run_node(StuckDouble))
''')


def test_a_node_stuck_in_its_spin_is_ended_by_the_watchdog_armed_by_the_signal(ros_domain):
    """SIGTERM never brings the main thread back from the callback; the watchdog its arrival armed ends it."""
    status, stderr = _signal_once_ready([STUCK_NODE, '1.0'], 'stuck', signal.SIGTERM, timeout=60)  # without it: never
    assert status == 1
    assert 'Timeout' in stderr and 'in stuck' in stderr    # the dump names the callback it hung in


def _ignore_sigint() -> None:
    """In the child before it runs its program: SIGINT ignored, as a shell starts a background job."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def test_a_node_whose_parent_ignores_sigint_ends_on_it_even_inside_a_callback(ros_domain):
    """rclpy's handler alone shuts the context down but cannot bring the main thread back from the
    callback; the node's own handler raises ``KeyboardInterrupt`` there, and the node ends normally.
    """
    status, stderr = _signal_once_ready([STUCK_NODE, '60.0'], 'stuck', signal.SIGINT, timeout=30,
                                        preexec_fn=_ignore_sigint)  # deaf to SIGINT, it would spin until killed
    assert status == 0, stderr
