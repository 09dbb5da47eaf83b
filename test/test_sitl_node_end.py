"""The sitl node when its SITL dies: the cause in one line, exit status 1, no traceback, no temp directory left;
the bringup naming that cause first, also when the node finds it only at the run's end; a --rate above SITL's
fixed speed-up refused in one line (issue 38, deliverable 5).

SITL here is a test double (a shell script that prints its arguments and sleeps): what is tested is the node's
and the bringup's handling of a child program that ends, whatever the program.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import psutil
import pytest

from tether_bringup.bringup import _failed_when_stopped
from tether_bringup.processes import ChildProcess
from tethersim_testing import tethersim
from test_uav_bridge_peer import wait_until

CAUSE = re.compile(r'SITL exited with status -9 \(killed by SIGKILL\) at sim time [\d.]+ s: the autopilot is gone')


@pytest.fixture
def sitl_double(tmp_path) -> Path:
    """An executable standing in for the SITL binary, with copter.parm beside it."""
    binary = tmp_path / 'bin' / 'arducopter'
    binary.parent.mkdir()
    binary.write_text('#!/bin/sh\necho "SITL double started: $*"\nexec sleep 600\n')
    binary.chmod(0o755)
    (binary.parent / 'copter.parm').write_text('FRAME_CLASS 1\n')
    return binary


def test_a_killed_sitl_ends_the_node_with_its_cause_and_its_temporary_directory_removed(sitl_double, ros_domain):
    node = subprocess.Popen([sys.executable, '-m', 'uav_bridge.sitl.node', '--ros-args', '-p', f'binary:={sitl_double}',
                             '-p', 'instance:=59'], env=dict(os.environ, ROS_DOMAIN_ID=str(ros_domain)),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        wait_until(lambda: [p for p in psutil.Process(node.pid).children() if 'sleep' in p.name()], timeout=60,
                   what='SITL (the double) running')
        sitl = next(p for p in psutil.Process(node.pid).children() if 'sleep' in p.name())
        workdir = Path(sitl.cwd())
        assert workdir.name.startswith('tethersim-sitl-') and workdir.is_dir()
        sitl.kill()
        output, _ = node.communicate(timeout=60)
    finally:
        if node.poll() is None:
            node.kill()
            node.communicate()
    assert node.returncode == 1, output
    assert 'Traceback' not in output and 'SystemExit' not in output
    lines = output.strip().splitlines()
    assert CAUSE.search(lines[-1]) and '[ERROR]' in lines[-1], output        # the cause, last
    assert 'SITL double started: --model +' in output                        # after SITL's last lines
    assert not workdir.exists()


def test_a_sitl_found_dead_only_at_the_end_fails_the_node(sitl_double, ros_domain, tmp_path):
    rclpy = pytest.importorskip('rclpy')
    from uav_bridge.sitl.node import SitlNode
    rclpy.init(args=['--ros-args', '-p', f'binary:={sitl_double}', '-p', 'instance:=59', '-p',
                     f'workdir:={tmp_path / "kept"}'])
    try:
        node = SitlNode()
        node.runner.process.send_signal(signal.SIGKILL)
        node.runner.process.wait(timeout=20)
        node.destroy_node()                     # the bringup stopped the node before its watch looked
    finally:
        rclpy.try_shutdown()
    assert CAUSE.match(node.failure)
    assert (tmp_path / 'kept' / 'sitl.log').is_file()            # a workdir the scene gave is kept


def test_a_node_exiting_with_an_error_when_stopped_fails_the_run_with_its_cause_first(tmp_path):
    cause = 'SITL exited with status -9 (killed by SIGKILL) at sim time 99.75 s: the autopilot is gone'
    script = ('import signal, sys, time\n'
              'def stop(*_):\n'
              f'    print("[ERROR] [1733300000.0] [sitl]: {cause} (found at the end of the run)", flush=True)\n'
              '    sys.exit(1)\n'
              'signal.signal(signal.SIGINT, stop)\n'
              'print("[INFO] [1733300000.0] [sitl]: SITL started", flush=True)\n'
              'time.sleep(60)\n')
    child = ChildProcess('sitl', [sys.executable, '-c', script], tmp_path / 'sitl.log', dict(os.environ))
    wait_until(lambda: 'SITL started' in (tmp_path / 'sitl.log').read_text(), what='the node')
    assert _failed_when_stopped([child]) is None                # still running
    child.stop()
    failure = _failed_when_stopped([child])
    assert failure is not None
    assert failure.splitlines()[0] == (f'node sitl ended with exit status 1: {cause} (found at the end of the run); '
                                       f'last lines of {tmp_path / "sitl.log"}:')


@pytest.mark.parametrize('rate', ['max', '8'])
def test_a_pace_sitl_cannot_follow_is_refused_in_one_line(rate, tmp_path):
    result = tethersim('run', 'outdoor_flight_sitl', '--rate', rate, '--out', str(tmp_path / 'run'))
    assert result.returncode == 2 and 'Traceback' not in result.stderr
    assert result.stderr.strip().splitlines() == [
        f'tethersim: error: node sitl: --rate {rate}: SITL runs at a fixed 4x wall time (its speedup), outside the '
        'lockstep, and the graph would outrun the autopilot; run at --rate 4 or less, or raise the speedup']
    assert not (tmp_path / 'run').exists()


def test_the_pace_of_sitl_on_the_json_physics_is_the_graphs():
    from uav_bridge.sitl.params import pace_problem
    assert pace_problem({'speedup': 4.0}, 4.0) is None
    assert pace_problem({'speedup': 4.0}, 4.5) is not None
    assert pace_problem({'speedup': 100.0, 'model': 'JSON:127.0.0.1'}, float('inf')) is None
