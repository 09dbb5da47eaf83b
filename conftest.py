"""What every test of the suite shares.

- Tests write only under pytest's temporary paths: the checkout is listed before and
  after the session; a file or directory that appeared outside the build products
  (``build``, ``install``, ``log``, the venv, caches) fails the session and is named, so a
  test that forgets ``--out tmp_path`` cannot go unnoticed.
- A test that talks DDS reserves its own ROS domain (``ros_domain``, ``ros_context``) with
  the allocator launch_testing uses, so two copies of the suite on one machine never
  share a domain.
"""

from __future__ import annotations

import os
from pathlib import Path

import domain_coordinator
import pytest

ROOT = Path(__file__).resolve().parent
NOT_CHECKED = frozenset({'.git', '.venv', 'build', 'install', 'log', '__pycache__', '.pytest_cache',
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
