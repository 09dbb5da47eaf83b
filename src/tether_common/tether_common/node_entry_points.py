"""The entry points packages register per node, by (package, executable).

A package names, under one entry-point group, something of each of its nodes: its class for
the node group (``tethersim.nodes``), its parameters module (``tethersim.parameters``). The
installed metadata does not change while a process runs, so each group is read once (a read
scans every installed distribution: about 8 ms here, and the bringup asks for each node).
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from importlib.metadata import EntryPoint
from importlib.metadata import entry_points
from types import MappingProxyType


@cache
def node_entry_points(group: str) -> Mapping[tuple[str, str], EntryPoint]:
    """The entry points of ``group`` by (package, executable): the distribution's name and the
    entry's name; nothing imported.
    """
    return MappingProxyType({(entry.dist.name.replace('-', '_') if entry.dist else '', entry.name): entry
                             for entry in entry_points(group=group)})
