"""The reel's guide height and the plant's clearance datum are one number."""

from __future__ import annotations

from smart_reel.reel_params import PARAMETERS
from tether_dynamics.clearance import GUIDE_HEIGHT


def test_the_reels_default_guide_height_is_the_datums():
    assert next(spec.default for spec in PARAMETERS if spec.name == 'guide_height') == GUIDE_HEIGHT
