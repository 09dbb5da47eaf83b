"""The ROS environment of a run: a private domain and localhost-only discovery by default."""

from __future__ import annotations

import os
import random

DISCOVERY_RANGES = {'localhost': 'LOCALHOST', 'subnet': 'SUBNET'}


def run_environment(domain_id: int | None, discovery: str, log_dir: str) -> dict[str, str]:
    """Return the environment for the nodes of a run.

    ``domain_id`` None picks a domain in 1..101 from the process id, so parallel runs on
    one machine do not see each other. ``discovery`` ``subnet`` lets the nodes of one scene
    span several machines (give every machine the same domain id).
    """
    env = dict(os.environ)
    if domain_id is None:
        domain_id = random.Random(os.getpid()).randint(1, 101)
    env['ROS_DOMAIN_ID'] = str(domain_id)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = DISCOVERY_RANGES[discovery]
    env.pop('ROS_LOCALHOST_ONLY', None)
    env['ROS_LOG_DIR'] = log_dir
    env['PYTHONUNBUFFERED'] = '1'
    env['RCUTILS_LOGGING_BUFFERED_STREAM'] = '0'
    return env
