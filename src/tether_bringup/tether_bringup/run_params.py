"""The parameters a run's nodes were started with, read back from its run directory.

The bringup writes each node's parameters to ``<run>/params/<node>.yaml`` (a ROS 2
parameter file with a ``/**`` section); reports read them back to interpret the bag.
"""

from __future__ import annotations

from pathlib import Path

import yaml


def node_parameter(path: str | Path, node: str, name: str):
    """A parameter of ``node`` from the run's ``params/<node>.yaml``; None without one.

    ``path`` may be the run directory, its bag directory or the bag's ``.mcap`` file.
    """
    start = Path(path).resolve()
    for directory in (start, *start.parents[:2]):
        file = directory / 'params' / f'{node}.yaml'
        if file.is_file():
            try:
                return yaml.safe_load(file.read_text())['/**']['ros__parameters'].get(name)
            except (yaml.YAMLError, KeyError, TypeError, AttributeError):
                return None
    return None
