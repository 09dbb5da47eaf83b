"""The one datum of the tether's clearance in every report: the deck.

The plant publishes the lowest point's height above the guide way (``/tether/state``
``clearance_deck``: the plant knows the guide way, not the deck) and above the sea
(``clearance_sea``). The smart reel stands on the deck with its guide way ``guide_height``
above it (the reel node's parameter); the reel's clearance trip, the fouling count and every
report's "lowest point above the deck" are ``clearance_deck + guide_height``, with the
``guide_height`` the run's reel was started with (``params/reel.yaml``), or the reel's
default for a run without a reel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tether_bringup.run_directory import node_parameter

GUIDE_HEIGHT = 0.3
"""m, the guide way above the deck: the reel node's default ``guide_height``."""


def guide_height(path: str | Path) -> float:
    """The ``guide_height`` of the run's reel (``params/reel.yaml`` beside the bag), else :data:`GUIDE_HEIGHT`."""
    value = node_parameter(path, 'reel', 'guide_height')
    try:
        return GUIDE_HEIGHT if value is None else float(value)
    except (TypeError, ValueError):
        return GUIDE_HEIGHT


def above_deck(clearance_deck: np.ndarray, height: float) -> np.ndarray:
    """The lowest point above the deck, m: ``/tether/state`` ``clearance_deck`` (above the guide way) + ``height``."""
    return np.asarray(clearance_deck) + height
