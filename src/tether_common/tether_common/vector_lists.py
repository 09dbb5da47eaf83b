"""Refill a message's sequence of x, y, z messages (geometry_msgs Point, Vector3) from an (n, 3) array.

A node that publishes the same message object at every step (``publish()`` serialises it at
once) reuses the sequence's elements: setting three floats on each costs a tenth of building
a new one with keyword arguments.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def fill_xyz(items: list, array: np.ndarray, factory: Callable[[], object]) -> None:
    """Make ``items`` as many as the rows of ``array`` (new ones from ``factory``, the surplus dropped)
    and set each one's x, y, z to its row.
    """
    rows = array.tolist()
    if len(items) != len(rows):
        del items[len(rows):]
        items.extend(factory() for _ in range(len(rows) - len(items)))
    for item, (x, y, z) in zip(items, rows):
        item.x, item.y, item.z = x, y, z
