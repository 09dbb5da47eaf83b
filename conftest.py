"""What every test of the suite shares.

- Tests write only under pytest's temporary paths: the checkout is listed before and
  after the session; a file or directory that appeared outside the build products
  (``build``, ``install``, ``log``, the venv, caches, ``.cache`` of the compiled kernels) fails the session and is named, so a
  test that forgets ``--out tmp_path`` cannot go unnoticed.
- ``make test`` runs the suite on two workers (pytest-xdist, a file per worker at a time,
  handed out in collection order: ``--no-loadscope-reorder``, since xdist would otherwise
  hand out the files with the most tests first); a module marked ``long_run`` (a scene
  against SITL for minutes) is collected first, so the two workers end together instead of
  one finishing a long run alone.
- A test that talks DDS reserves its own ROS domain (``ros_domain``, ``ros_context``) with
  the allocator launch_testing uses, so two copies of the suite on one machine never
  share a domain.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import domain_coordinator
import pytest

ROOT = Path(__file__).resolve().parent
NOT_CHECKED = frozenset({'.git', '.venv', 'build', 'install', 'log', '__pycache__', '.cache', '.pytest_cache',
                         '.mypy_cache', '.ruff_cache'})


def tree_listing(root: Path) -> set[str]:
    """Every path under ``root`` (relative, ``/``-separated), build products and caches left out."""
    found: set[str] = set()
    for directory, subdirectories, files in os.walk(root):
        subdirectories[:] = [d for d in subdirectories if d not in NOT_CHECKED and not d.endswith('.egg-info')]
        base = Path(directory).relative_to(root)
        found.update((base / name).as_posix() for name in (*subdirectories, *files))
    return found


def pytest_sessionstart(session: pytest.Session) -> None:
    session.config.stash[_BEFORE] = tree_listing(ROOT)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    before = session.config.stash.get(_BEFORE, None)
    if before is None:
        return
    written = sorted(tree_listing(ROOT) - before)
    if written:
        shown = ', '.join(written[:10]) + (f' and {len(written) - 10} more' if len(written) > 10 else '')
        print(f'\nthe test session wrote into the checkout {ROOT}: {shown}', flush=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


_BEFORE = pytest.StashKey[set]()


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line('markers', 'long_run: runs for minutes; scheduled before the rest')


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Long runs first, the rest in collection order (every worker sorts alike)."""
    items.sort(key=lambda item: item.get_closest_marker('long_run') is None)


@pytest.fixture
def ros_domain(monkeypatch):
    """A ROS_DOMAIN_ID reserved for this test alone, discovery on localhost, set in the environment."""
    with domain_coordinator.domain_id() as domain:
        monkeypatch.setenv('ROS_DOMAIN_ID', str(domain))
        monkeypatch.setenv('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
        yield domain


@pytest.fixture
def ros_context(ros_domain):
    """An rclpy context initialised in the test's reserved domain."""
    import rclpy
    context = rclpy.Context()
    rclpy.init(context=context)
    yield context
    rclpy.shutdown(context=context)


class LockstepMaster:
    """A test probe as the run's time master: ``/clock`` advances only once every member node
    has acked the last step (the bringup's :class:`~tether_bringup.barrier.Barrier`), so what
    the nodes publish does not depend on how fast they run.

    Start the member processes with :meth:`environment`, so each joins only once every member
    and the probe are in the graph, as in a run. The first step goes out only once the probe's
    own publishers have matched every subscription of their topics (``/clock``: one per
    member): a node's subscription matching the probe's publisher does not mean the probe's
    publisher has matched it, and a message published before that is lost to the node.
    """

    def __init__(self, node, members: list[str], processes) -> None:
        from rosgraph_msgs.msg import Clock
        from tether_bringup.barrier import Barrier
        self._node, self._processes, self._message, self._members = node, processes, Clock, members
        self._clock = node.create_publisher(Clock, '/clock', 10)
        self._barrier = Barrier(node, members)

    @staticmethod
    def environment(probe: str, members: list[str]) -> dict[str, str]:
        """The variable to add to member processes' environment: the run's node names (``TETHERSIM_NODES``)."""
        from tether_common.lockstep import NODES_VARIABLE
        return {NODES_VARIABLE: ','.join([probe, *(name.lstrip('/') for name in members)])}

    def _matched(self) -> bool:
        from tether_common.lockstep import publishers_matched
        return self._clock.get_subscription_count() >= len(self._members) and publishers_matched(self._node)

    def _wait(self, done, what) -> None:
        import rclpy
        deadline = time.monotonic() + 120.0
        while not done():
            if time.monotonic() > deadline:
                for p in self._processes:
                    p.kill()
                logs = [''.join(part or '' for part in p.communicate()) for p in self._processes]
                raise AssertionError(f'{what()} within 120 s; the nodes printed: {logs}')
            ended = [p.args for p in self._processes if p.poll() is not None]
            assert not ended, f'node process(es) ended early: {ended}'
            rclpy.spin_once(self._node, timeout_sec=0.01)

    def wait_acked(self, time_ns: int) -> None:
        """Spin until every member has acked ``time_ns`` (0: joined, and the probe's publishers matched);
        a guard against a hang, not a speed limit.
        """
        self._wait(lambda: self._barrier.reached(time_ns) and (time_ns > 0 or self._matched()),
                   lambda: f'no ack of {time_ns} ns from {self._barrier.behind(time_ns)}' if self._barrier.behind(
                       time_ns) else 'the probe\'s publishers did not match every subscription')

    def stop(self, timeout: float = 30.0) -> list[str]:
        """SIGINT every member process and return what each printed (its output, then its errors).

        One still running after ``timeout`` is aborted: SIGABRT makes the faulthandler the
        executor enabled print every thread's stack into its output, so the test fails on the
        process's status, shows where it hung, and leaves no process behind.
        """
        for p in self._processes:
            p.send_signal(signal.SIGINT)
        deadline = time.monotonic() + timeout
        logs = []
        for p in self._processes:
            try:
                parts = p.communicate(timeout=max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                p.send_signal(signal.SIGABRT)
                try:
                    parts = p.communicate(timeout=10.0)
                except subprocess.TimeoutExpired:
                    p.kill()
                    parts = p.communicate()
            logs.append(''.join(part or '' for part in parts))
        return logs

    def step_to(self, time_ns: int) -> None:
        """Publish ``/clock`` at ``time_ns`` and wait until every member has run up to it."""
        msg = self._message()
        msg.clock.sec, msg.clock.nanosec = divmod(time_ns, 1_000_000_000)
        self._clock.publish(msg)
        self.wait_acked(time_ns)


@pytest.fixture
def lockstep_master():
    """The :class:`LockstepMaster` class, for a probe node driving ``/clock`` in a test."""
    return LockstepMaster
