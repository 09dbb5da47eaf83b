"""``tethersim report campaign``: Wilson intervals, success per grid level, figure distributions, worst runs."""

from __future__ import annotations

import math

import pytest
import yaml

from tether_bringup.cli import main
from tether_campaign.report import Z_95
from tether_campaign.report import wilson_interval
from tether_campaign.results import read_table
from tether_campaign.results import write_row
from tether_campaign.results import write_tables


@pytest.mark.parametrize('wins, runs', [(0, 10), (5, 10), (10, 10), (1, 3), (57, 60), (0, 1)])
def test_the_wilson_interval_holds_the_proportions_the_score_test_does_not_reject(wins, runs):
    low, high = wilson_interval(wins, runs)
    p = wins / runs
    assert 0.0 <= low <= p <= high <= 1.0
    # the ends are the roots of |p - p0| = z sqrt(p0 (1 - p0) / n), except where clipped at 0 or 1
    for end in (low, high):
        if 0.0 < end < 1.0:
            assert abs(p - end) == pytest.approx(Z_95 * math.sqrt(end * (1 - end) / runs), rel=1e-9)
        else:
            assert end == p
    with pytest.raises(ValueError):
        wilson_interval(3, 2)


def test_the_wilson_interval_of_textbook_cases():
    assert wilson_interval(0, 10) == pytest.approx((0.0, 0.27753), abs=1e-5)
    assert wilson_interval(5, 10) == pytest.approx((0.23659, 0.76341), abs=1e-5)


def _campaign(tmp_path):
    directory = tmp_path / 'campaign'
    directory.mkdir()
    (directory / 'campaign.yaml').write_text(yaml.safe_dump(
        {'factors': ['platform.profile', 'platform.seed'], 'grid': ['platform.profile']}))
    outcomes = ['landed_on_pad', 'aborted', 'landed_on_pad', 'landed_on_pad', 'landed_on_pad', 'aborted']
    for index, outcome in enumerate(outcomes):
        row = {'index': index, 'run': f'run-{index:04d}', 'status': 'ok', 'attempts': 1, 'reason': None,
               'command': f'tethersim run c/runs/run-{index:04d}/outdoor_flight.yaml --out runs/rerun-run-{index:04d}',
               'platform.profile': ['hpr1', 'hpr2'][index % 2], 'platform.seed': 100 + index,
               'exit_status': 0, 'outcome': outcome, 'success': outcome == 'landed_on_pad',
               'abort_reason': 'reel trip: tension' if outcome == 'aborted' else None,
               'peak_tension_reel': 10.0 + index, 'hold_time': 100.0 - index}
        write_row(directory, row)
    write_row(directory, {'index': 6, 'run': 'run-0006', 'status': 'failed', 'attempts': 3,
                          'reason': 'exit status 1: node nodes died', 'command': 'tethersim run x --out y',
                          'platform.profile': 'hpr1', 'platform.seed': 106, 'exit_status': 1})
    assert write_tables(directory) == 7
    return directory


def test_the_report_of_a_campaign(tmp_path, capsys):
    directory = _campaign(tmp_path)
    rows = read_table(directory)
    assert [row['peak_tension_reel'] for row in rows] == [10.0, 11.0, 12.0, 13.0, 14.0, 15.0, None]
    assert main(['report', 'campaign', str(directory), '--count', '4']) == 0
    text = (directory / 'report' / 'summary.txt').read_text()
    assert text == capsys.readouterr().out
    low, high = wilson_interval(4, 7)
    assert (f'success rate: 4/7 succeeded, 57.1 % (95 % Wilson {100 * low:.1f}-{100 * high:.1f} %)') in text
    assert '  hpr1: 3/4 succeeded, 75.0 %' in text and '  hpr2: 1/3 succeeded, 33.3 %' in text
    assert 'by platform.seed' not in text
    assert 'outcomes: aborted 2, landed_on_pad 4' in text
    assert 'peak_tension_reel                6        12.5        12.5' in text
    worst = text[text.index('worst runs'):].splitlines()
    assert worst[1].startswith('  run-0006: failed after 3 attempt(s): exit status 1: node nodes died;')
    assert worst[2] == '    rerun alone: tethersim run x --out y'
    assert worst[3].startswith('  run-0001: outcome aborted: reel trip: tension; platform.profile hpr2, platform.seed 101')
    assert worst[5].startswith('  run-0005: outcome aborted')
    assert worst[7].startswith('  run-0004: peak_tension_reel 14;')
    assert worst[8] == ('    rerun alone: tethersim run c/runs/run-0004/outdoor_flight.yaml --out runs/rerun-run-0004')
    assert len(worst) == 10
    for name in ('peak_tension_reel', 'hold_time'):
        assert (directory / 'report' / f'figure_{name}.png').stat().st_size > 0


def test_a_bad_report_request_is_one_line_with_status_2(tmp_path, capsys):
    directory = _campaign(tmp_path)
    assert main(['report', 'campaign', str(directory), '--worst', 'nonsense', '--out', str(tmp_path / 'r')]) == 2
    err = capsys.readouterr().err
    assert err.count('\n') == 1 and '--worst nonsense: not a numeric figure of the runs' in err
    assert not (tmp_path / 'r').exists()
    assert main(['report', 'campaign', str(tmp_path), '--out', str(tmp_path / 'r')]) == 2
    assert 'no results.parquet' in capsys.readouterr().err
