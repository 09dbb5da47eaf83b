"""Campaign specs: runs fixed by the spec and their index, and bad specs refused in one line with exit status 2."""

from __future__ import annotations

import socket

import pytest
import yaml

from tether_bringup.cli import main
from tether_campaign.spec import SpecError
from tether_campaign.spec import load_campaign

SPEC = {
    'description': 'test',
    'scene': 'platform',
    'count': 3,
    'seed': 7,
    'set': {'duration': 2.0, 'rate': 'max'},
    'grid': {'platform.profile': ['hpr1', 'hpr2'], 'platform.ramp_time': [1.0, 2.0, 3.0]},
    'random': {'platform.seed': {'range': [1, 1000]}, 'platform.profile_duration': {'uniform': [10.0, 20.0]}},
}


def _write(tmp_path, spec: dict, name: str = 'spec.yaml'):
    path = tmp_path / name
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def test_runs_are_fixed_by_the_spec_and_their_index(tmp_path):
    campaign = load_campaign(_write(tmp_path, SPEC))
    assert campaign.size == 3 * 2 * 3
    assert campaign.factors == ['platform.profile', 'platform.ramp_time', 'platform.seed', 'platform.profile_duration']
    again = load_campaign(_write(tmp_path, SPEC, 'again.yaml'))
    values = [campaign.values(i) for i in range(campaign.size)]
    assert values == [again.values(i) for i in range(again.size)]
    # the first runs cover every grid point, then the points repeat with new draws
    points = [(v['platform.profile'], v['platform.ramp_time']) for v in values]
    assert len(set(points[:6])) == 6 and points[6:12] == points[:6] and points[12:] == points[:6]
    assert len({v['platform.seed'] for v in values}) > 12
    for v in values:
        assert isinstance(v['platform.seed'], int) and 1 <= v['platform.seed'] <= 1000
        assert 10.0 <= v['platform.profile_duration'] < 20.0
        assert v['duration'] == 2.0 and v['rate'] == 'max'
    scene = campaign.scene(4)
    platform = next(node for node in scene.nodes if node.name == 'platform')
    assert platform.parameters['seed'] == values[4]['platform.seed']
    assert platform.parameters['ramp_time'] == values[4]['platform.ramp_time']
    assert scene.duration == 2.0


def test_a_keys_draws_do_not_depend_on_the_other_keys_or_the_grid(tmp_path):
    campaign = load_campaign(_write(tmp_path, SPEC))
    fewer = dict(SPEC, grid={}, random={'platform.seed': {'range': [1, 1000]}})
    other = load_campaign(_write(tmp_path, fewer, 'fewer.yaml'))
    assert [other.values(i)['platform.seed'] for i in range(3)] == [campaign.values(i)['platform.seed'] for i in range(3)]
    reseeded = load_campaign(_write(tmp_path, dict(SPEC, seed=8), 'reseeded.yaml'))
    assert [reseeded.values(i)['platform.seed'] for i in range(6)] != [campaign.values(i)['platform.seed'] for i in range(6)]


def test_the_run_scene_is_the_base_scene_with_the_values(tmp_path):
    campaign = load_campaign(_write(tmp_path, SPEC))
    data = campaign.scene_data(5)
    base = yaml.safe_load(campaign.scene_path.read_text())
    parameters = dict(base['nodes']['platform']['parameters'])
    parameters.update({key.partition('.')[2]: value for key, value in campaign.values(5).items() if '.' in key})
    assert data['nodes']['platform']['parameters'] == parameters
    assert data['reports'] == base['reports'] and data['duration'] == 2.0


@pytest.mark.parametrize('change, message', [
    ({'grid': {'platfrom.profile': ['hpr1']}}, "grid.platfrom.profile: no node 'platfrom' in scene platform"),
    ({'grid': {'platform.profil': ['hpr1']}}, 'grid.platform.profil: unknown parameter of psr_platform_sim/platform'),
    ({'grid': {'platform.ramp_time': ['slow']}}, 'grid.platform.ramp_time: '),
    ({'grid': {'platform.profile': ['hpr1', 'hpr9']}}, 'grid.platform.profile: '),
    ({'grid': {'platform.profile': []}}, 'grid.platform.profile: expected a non-empty list of values'),
    ({'random': {'platform.seed': {'normal': [0, 1]}}}, 'random.platform.seed: expected {uniform: [a, b]}'),
    ({'random': {'platform.seed': {'range': [5, 1]}}}, 'random.platform.seed: range: expected two integers a <= b'),
    ({'random': {'platform.profile': {'uniform': [0, 1]}}}, 'random.platform.profile: '),
    ({'set': {'records': 3}}, 'set.records: expected node.parameter or one of the scene keys'),
    ({'count': 0}, 'count: expected an integer >= 1'),
    ({'scene': 'no_such_scene'}, 'scene: no_such_scene: no such scene'),
    ({'sweeps': 3}, 'sweeps: unknown key'),
])
def test_a_bad_spec_is_refused_in_one_line_with_status_2_before_anything_starts(tmp_path, capsys, change, message):
    spec = _write(tmp_path, {**SPEC, **change})
    with pytest.raises(SpecError):
        load_campaign(spec)
    out = tmp_path / 'campaign'
    assert main(['sweep', str(spec), '--out', str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and err.startswith('tethersim: error: ') and message in err, err
    assert not out.exists()


def test_an_address_where_no_cluster_listens_is_one_line_with_status_2_before_anything_starts(tmp_path, capsys):
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        port = sock.getsockname()[1]
    out = tmp_path / 'campaign'
    assert main(['sweep', str(_write(tmp_path, SPEC)), '--out', str(out), '--address', f'127.0.0.1:{port}']) == 2
    err = capsys.readouterr().err
    assert err == f'tethersim: error: cannot connect to the Ray cluster at 127.0.0.1:{port}: Connection refused\n'
    assert not out.exists()
