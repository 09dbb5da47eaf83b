"""``tethersim estimator evaluate`` and ``tune`` on the reference recordings of bags/ (bags/README.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yaml

from relpos_estimator.cli import main
from relpos_estimator.estimator_params import PARAMETERS
from relpos_estimator.twiddle import twiddle

BAGS = Path(__file__).resolve().parents[3] / 'bags'
HPR3 = BAGS / 'estimator-hpr3-40s'
STILL = BAGS / 'estimator-still-40s'


def test_twiddle_finds_the_minimum_of_a_bowl_and_keeps_parameters_positive():
    seen = []

    def cost(p):
        seen.append(p.copy())
        return float(np.sum((np.log(p) - np.log([0.02, 3.0])) ** 2))

    p, best, rounds = twiddle(cost, np.array([1.0, 1.0]), np.array([0.4, 0.4]), tolerance=0.01)
    assert np.all(np.array(seen) > 0)
    np.testing.assert_allclose(p, [0.02, 3.0], rtol=0.1)
    assert best < 0.01 and rounds > 1


def _table(text: str) -> list[str]:
    """The lines of an evaluate output that hold numbers (rows, faults, checks), without the source line."""
    return [line for line in text.splitlines() if line.startswith(('estimator-', 'PASS', 'FAIL'))]


def test_evaluate_gives_the_same_table_every_time(tmp_path, capsys):
    assert main(['evaluate', str(HPR3), '--out', str(tmp_path / 'a')]) == 0
    first = capsys.readouterr().out
    assert main(['evaluate', str(HPR3), '--out', str(tmp_path / 'b')]) == 0
    assert capsys.readouterr().out.replace(str(tmp_path / 'b'), '') == first.replace(str(tmp_path / 'a'), '')
    row = next(line for line in first.splitlines() if line.startswith('estimator-hpr3-40s '))
    filter_rmse, foh_rmse = float(row.split()[3]), float(row.split()[5])
    assert filter_rmse < 0.5 * foh_rmse
    assert 'FAIL' not in first
    assert (tmp_path / 'a' / 'evaluate.png').stat().st_size > 0


def test_replay_through_the_node_gives_the_numbers_of_the_direct_run(tmp_path, capsys):
    """The estimator node behind tethersim replay publishes exactly what the core gives on the decoded messages."""
    from relpos_estimator.cli import _factory
    from relpos_estimator.cli import load_parameters
    from relpos_estimator.estimator_params import tuned_file
    from relpos_estimator.recorded import read_outputs
    from relpos_estimator.recorded import read_recording
    from relpos_estimator.recorded import replay

    assert main(['evaluate', str(STILL), '--replay', '--out', str(tmp_path / 'replay')]) == 0
    via_replay = capsys.readouterr().out
    assert main(['evaluate', str(STILL), '--out', str(tmp_path / 'direct')]) == 0
    direct = capsys.readouterr().out
    assert 'tethersim replay' in via_replay and 'directly' in direct
    assert _table(via_replay) == _table(direct) and len(_table(direct)) >= 2
    node = read_outputs(tmp_path / 'replay' / 'replay-estimator-still-40s')
    values = load_parameters(tuned_file())
    core = replay(read_recording(STILL), _factory(values)(), input_delay=values['input_delay'])
    assert sorted(node.ticks) == sorted(core.ticks) and node.rejected == core.rejected
    stamps = sorted(core.ticks)
    np.testing.assert_array_equal(np.array([node.ticks[t] for t in stamps], dtype=float),
                                  np.array([core.ticks[t] for t in stamps], dtype=float))


def test_tune_writes_a_parameter_file_that_evaluate_loads(tmp_path, capsys):
    assert main(['tune', str(HPR3), '--max-rounds', '1', '--out', str(tmp_path)]) == 0
    out = capsys.readouterr().out
    before = float(out.split('RMSE ')[1].split(' mm')[0])
    after = float(out.split('-> ')[1].split(' mm')[0])
    assert after <= before
    params = yaml.safe_load((tmp_path / 'tuned.yaml').read_text())['/**']['ros__parameters']
    names = {s.name for s in PARAMETERS}
    assert set(params) <= names and all(v > 0 for v in params.values())
    assert main(['evaluate', str(HPR3), '--no-shift', '--params', str(tmp_path / 'tuned.yaml'),
                 '--out', str(tmp_path / 'e')]) == 0


def test_user_mistakes_are_one_line_errors(tmp_path, capsys):
    assert main(['evaluate', str(tmp_path / 'nothing'), '--out', str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.splitlines()[-1].startswith('tethersim estimator: error:') and 'Traceback' not in err
    bad = tmp_path / 'bad.yaml'
    bad.write_text('/**:\n  ros__parameters:\n    sigma_z: -1.0\n')
    assert main(['evaluate', str(HPR3), '--params', str(bad), '--out', str(tmp_path)]) == 2
    assert 'sigma_z' in capsys.readouterr().err
