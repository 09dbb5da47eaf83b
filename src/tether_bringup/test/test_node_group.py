"""The node group: which nodes can join it, its spec and CPU files, and the scene keys that choose it."""

from __future__ import annotations

import pytest

from tether_bringup.errors import SceneError
from tether_bringup.node_group import GROUP_NAME
from tether_bringup.node_group import node_classes
from tether_bringup.node_group import read_cpu
from tether_bringup.node_group import write_spec
from tether_bringup.scene import load_scene


def test_tethersims_lockstep_nodes_are_registered_and_the_bridges_to_simulators_are_not():
    classes = node_classes()
    assert {('psr_platform_sim', 'platform'), ('tether_dynamics', 'plant'), ('smart_reel', 'reel'),
            ('relpos_estimator', 'sensors'), ('relpos_estimator', 'estimator'), ('uav_bridge', 'builtin_uav'),
            ('uav_bridge', 'mission')} <= set(classes)
    assert not {('uav_bridge', 'sitl'), ('uav_bridge', 'json_physics'), ('uav_bridge', 'mavlink_bridge'),
                ('tether_bringup', 'recorder')} & set(classes)
    assert classes['tether_dynamics', 'plant'].load().__name__ == 'PlantNode'


def test_spec_names_each_node_and_cpu_file_reads_back(tmp_path):
    write_spec(tmp_path / 'spec.yaml', tmp_path / 'cpu.yaml', [('plant', 'tether_dynamics', 'plant', tmp_path / 'p.yaml')])
    assert (tmp_path / 'spec.yaml').read_text() == (
        f'cpu_file: {tmp_path / "cpu.yaml"}\nrecord_fd: -1\nnodes:\n- name: plant\n  package: tether_dynamics\n  executable: plant\n'
        f'  params_file: {tmp_path / "p.yaml"}\n')
    (tmp_path / 'cpu.yaml').write_text('plant: 1.5\nreel: 0.25\n')
    assert read_cpu(tmp_path / 'cpu.yaml') == {'plant': 1.5, 'reel': 0.25}
    assert read_cpu(tmp_path / 'missing.yaml') == {}
    (tmp_path / 'bad.yaml').write_text('[unclosed')
    assert read_cpu(tmp_path / 'bad.yaml') == {}


SCENE = 'description: x\n{extra}nodes:\n  {name}:\n    package: psr_platform_sim\n    executable: platform\n'


def test_compose_is_on_unless_the_scene_turns_it_off(tmp_path):
    path = tmp_path / 'scene.yaml'
    path.write_text(SCENE.format(extra='', name='platform'))
    assert load_scene(path).compose is True
    path.write_text(SCENE.format(extra='compose: false\n', name='platform'))
    assert load_scene(path).compose is False
    path.write_text(SCENE.format(extra='compose: sometimes\n', name='platform'))
    with pytest.raises(SceneError, match='compose: expected a boolean'):
        load_scene(path)


@pytest.mark.parametrize('name', ['tethersim', 'recorder', GROUP_NAME])
def test_a_node_may_not_take_the_name_of_a_bringup_process(tmp_path, name):
    path = tmp_path / 'scene.yaml'
    path.write_text(SCENE.format(extra='', name=name))
    with pytest.raises(SceneError, match=f'nodes.{name}: .* names a process of the bringup itself'):
        load_scene(path)
