"""The ROS environment of a run: a private domain and localhost-only discovery by default."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator

import domain_coordinator

from tether_bringup.errors import RunError

DISCOVERY_RANGES = {'localhost': 'LOCALHOST', 'subnet': 'SUBNET'}


@contextlib.contextmanager
def reserved_domain(domain_id: int | None) -> Iterator[int]:
    """Yield ``domain_id``, or if it is None a ``ROS_DOMAIN_ID`` no other run holds.

    The private domain is reserved with ``domain_coordinator`` (the allocator
    launch_testing and ament_cmake_pytest_isolated use: a TCP port 32768 + id held open
    for as long as the context lasts), so runs, test suites and launch tests started at
    the same time on one machine each get their own domain in 1..100. An explicit
    ``domain_id`` (a scene spanning machines) is used as given.
    """
    if domain_id is not None:
        yield domain_id
        return
    failure: OSError | None = None
    try:
        with domain_coordinator.domain_id() as reserved:
            try:
                yield reserved
            except OSError as error:  # the allocator would take it for a busy port and retry
                failure = error
    except RuntimeError:
        raise RunError('every private ROS domain (1-100) is held by another run; '
                       'wait for one to end or give --domain-id') from None
    if failure is not None:
        raise failure


def run_environment(domain_id: int, discovery: str, log_dir: str) -> dict[str, str]:
    """Return the environment for the nodes of a run in ``domain_id``.

    ``discovery`` ``subnet`` lets the nodes of one scene span several machines (give every
    machine the same domain id).
    """
    env = dict(os.environ)
    env['ROS_DOMAIN_ID'] = str(domain_id)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = DISCOVERY_RANGES[discovery]
    env.pop('ROS_LOCALHOST_ONLY', None)
    env['ROS_LOG_DIR'] = log_dir
    env['PYTHONUNBUFFERED'] = '1'
    env['RCUTILS_LOGGING_BUFFERED_STREAM'] = '0'
    return env
