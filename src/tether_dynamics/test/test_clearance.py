"""One datum for clearances: the deck, the run's reel guide_height below the guide way; the element count's range."""

from __future__ import annotations

import numpy as np
import yaml

from tether_dynamics.clearance import GUIDE_HEIGHT
from tether_dynamics.clearance import above_deck
from tether_dynamics.clearance import guide_height
from tether_dynamics.plant_report import TetherRun
from tether_dynamics.plant_report import _model


def _run_dir(tmp_path, reel: dict | None):
    (tmp_path / 'bag').mkdir()
    if reel is not None:
        (tmp_path / 'params').mkdir()
        (tmp_path / 'params' / 'reel.yaml').write_text(yaml.safe_dump({'/**': {'ros__parameters': reel}}))
    return tmp_path / 'bag'


def test_the_guide_height_is_the_runs_reel_parameter_from_the_bag_or_run_directory(tmp_path):
    bag = _run_dir(tmp_path, {'guide_height': 0.45})
    assert guide_height(bag) == 0.45
    assert guide_height(tmp_path) == 0.45


def test_without_a_reel_the_guide_height_is_the_reels_default(tmp_path):
    assert guide_height(_run_dir(tmp_path, None)) == GUIDE_HEIGHT == 0.3


def test_above_the_deck_adds_the_guide_height_to_the_plants_clearance_below_the_guide_way():
    assert np.allclose(above_deck(np.array([-0.02, 1.0]), 0.3), [0.28, 1.3])


def _tether_run(fidelity: str, elements: int, element_range: tuple[int, int]) -> TetherRun:
    empty = np.zeros(0)
    return TetherRun(t=empty, reel_end=empty, uav_end=empty, length=empty, tension_reel=empty, tension_uav=empty,
                     departure=empty, arrival=empty, deck=empty, clearance_sea=empty, fouling=empty,
                     fidelity=fidelity, elements=elements, element_range=element_range, guide_height=0.3,
                     node_t=empty, nodes=[])


def test_the_report_says_why_the_element_count_varies():
    assert _model(_tether_run('linear', 20, (20, 20))) == 'linear, 20 elements'
    text = _model(_tether_run('linear', 20, (19, 21)))
    assert text.startswith('linear, 20 elements set, 19-21 over the run') and 'splits and merges' in text
    assert _model(_tether_run('quasi_static', 20, (20, 20))) == 'quasi_static'
