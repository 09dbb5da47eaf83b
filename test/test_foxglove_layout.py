"""The saved Foxglove/Lichtblick layout (config/foxglove_layout.json) refers only to what a run publishes.

Each panel the layout tree places has a configuration and each configuration is placed; each
plotted or charted message path names a field of its topic's message type; the 3-D panel
follows ``world`` and shows the markers and the poses (all in ``world``: test_live_view).
"""

from __future__ import annotations

import json

from tether_common.message_types import message_class

from tethersim_testing import ROOT

LAYOUT = ROOT / 'config' / 'foxglove_layout.json'
TOPIC_TYPES = {
    '/tether/state': 'tether_msgs/msg/TetherState',
    '/mission/state': 'tether_msgs/msg/MissionState',
    '/tether/markers': 'visualization_msgs/msg/MarkerArray',
    '/platform/reel_pose': 'geometry_msgs/msg/PoseStamped',
    '/uav/pose': 'geometry_msgs/msg/PoseStamped',
    '/uav/setpoint': 'geometry_msgs/msg/PoseStamped',
}
"""The types of the topics the layout shows, as the nodes publish them (the bags' schema names)."""


def _placed(tree) -> list[str]:
    if isinstance(tree, str):
        return [tree]
    return _placed(tree['first']) + _placed(tree['second'])


def _paths(config: dict) -> list[str]:
    return [path['value'] for path in config.get('paths', [])] + \
        ([config['topicPath']] if 'topicPath' in config else [])


def test_every_panel_is_placed_and_configured():
    layout = json.loads(LAYOUT.read_text())
    assert sorted(_placed(layout['layout'])) == sorted(layout['configById'])
    kinds = {panel.split('!')[0] for panel in layout['configById']}
    assert {'3D', 'Plot', 'StateTransitions'} <= kinds


def test_message_paths_name_fields_of_their_topics_types():
    layout = json.loads(LAYOUT.read_text())
    paths = [path for config in layout['configById'].values() for path in _paths(config)]
    assert {'/tether/state.tension_reel', '/tether/state.clearance_sea', '/mission/state.phase'} <= set(paths)
    for path in paths:
        topic, _, field = path.partition('.')
        assert topic in TOPIC_TYPES, path
        if field:
            assert field in message_class(TOPIC_TYPES[topic]).get_fields_and_field_types(), path


def test_three_d_panel_shows_the_world_frame_topics():
    panel = next(config for name, config in json.loads(LAYOUT.read_text())['configById'].items()
                 if name.startswith('3D!'))
    assert panel['followTf'] == 'world'
    assert set(panel['topics']) == {topic for topic, kind in TOPIC_TYPES.items()
                                    if kind.endswith(('MarkerArray', 'PoseStamped'))}
