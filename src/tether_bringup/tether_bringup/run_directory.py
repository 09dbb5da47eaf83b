"""The parameters a run's nodes were started with, read back from its run directory.

The bringup writes each node's parameters to ``<run>/params/<node>.yaml`` (a ROS 2
parameter file with a ``/**`` section) as the scene gave them; reports read them back to
interpret the bag, falling back to the default the node declares for one the scene left out.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from tether_bringup.scene import parameter_specs


def node_parameter(path: str | Path, node: str, name: str, declared: tuple[str, str] | None = None):
    """A parameter of ``node`` from the run's ``params/<node>.yaml``; when the file does not set it, the
    default that ``declared`` (package, executable) declares; None without either.

    ``path`` may be the run directory, its bag directory or the bag's ``.mcap`` file.
    """
    start = Path(path).resolve()
    for directory in (start, *start.parents[:2]):
        file = directory / 'params' / f'{node}.yaml'
        if file.is_file():
            try:
                value = yaml.safe_load(file.read_text())['/**']['ros__parameters'].get(name)
            except (yaml.YAMLError, KeyError, TypeError, AttributeError):
                return None
            if value is None and declared is not None:
                specs = {spec.name: spec for spec in parameter_specs(*declared) or ()}
                value = specs[name].default if name in specs else None
            return value
    return None
