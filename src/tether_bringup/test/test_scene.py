"""Scene loading: defaults, coercion, installed scenes."""

from __future__ import annotations

import pytest

from tether_bringup.errors import SceneError
from tether_bringup.scene import find_scene
from tether_bringup.scene import list_scenes
from tether_bringup.scene import load_scene


def test_defaults_and_coercion(tmp_path):
    path = tmp_path / 's.yaml'
    path.write_text('description: d\nduration: 5\nnodes:\n  rec:\n    package: tether_bringup\n'
                    '    executable: recorder\n    parameters: {flush_period: 1, exclude: [/a]}\n')
    scene = load_scene(path)
    assert (scene.duration, scene.rate, scene.clock_step) == (5.0, 1.0, 0.01)
    assert scene.nodes[0].parameters == {'flush_period': 1.0, 'exclude': ['/a']}
    assert isinstance(scene.nodes[0].parameters['flush_period'], float)
    assert scene.nodes[0].command[0].endswith('lib/tether_bringup/recorder')
    assert sorted(scene.exclude) == ['/parameter_events', '/rosout']


def test_record_exclude_and_reports_are_checked(tmp_path):
    path = tmp_path / 's.yaml'
    path.write_text('description: d\nrecord: {excluded: [/a]}\nnodes:\n  rec:\n    package: tether_bringup\n'
                    '    executable: recorder\n')
    with pytest.raises(SceneError, match=r'record\.excluded: unknown key'):
        load_scene(path)
    path.write_text('description: d\nreports: [nocolon]\nnodes:\n  rec:\n    package: tether_bringup\n'
                    '    executable: recorder\n')
    with pytest.raises(SceneError, match='reports: expected module:function'):
        load_scene(path)


def test_every_installed_scene_is_valid():
    scenes = list_scenes()
    assert scenes, 'no installed scenes'
    for name, description in scenes:
        assert not description.startswith('(invalid'), (name, description)
        assert load_scene(find_scene(name)).nodes


def test_rate_max_means_no_pacing(tmp_path):
    path = tmp_path / 's.yaml'
    path.write_text('description: d\nrate: max\nnodes:\n  rec:\n    package: tether_bringup\n'
                    '    executable: recorder\n')
    assert load_scene(path).rate == float('inf')
    path.write_text('description: d\nrate: fastest\nnodes:\n  rec:\n    package: tether_bringup\n'
                    '    executable: recorder\n')
    with pytest.raises(SceneError, match='rate: expected a number'):
        load_scene(path)
