"""``tethersim sweep`` on a local Ray instance: runs equal to the same scenes run alone, retries, resume, Ctrl-C.

The campaigns are of the platform scene for 2-4 s of sim time, so that each test stays near
a minute on a loaded 2-core machine.
"""

from __future__ import annotations

import csv
import json
import signal
import time
from pathlib import Path

import pyarrow.parquet as pq
from campaign_testing import ProcessWatch
from campaign_testing import run_figures
from campaign_testing import simulated
from campaign_testing import write_spec
from tethersim_testing import differing_topics
from tethersim_testing import processes_of
from tethersim_testing import start_tethersim
from tethersim_testing import tethersim

NODES = Path(__file__).resolve().parent / 'nodes'


def test_a_campaign_run_equals_the_same_scene_run_alone(tmp_path):
    spec = write_spec(tmp_path / 'four.yaml', description='four short platform runs', scene='platform', count=2,
                      set={'duration': 2.0, 'rate': 'max'}, grid={'platform.profile': ['hpr1', 'hpr3']},
                      random={'platform.seed': {'range': [1, 1000]}})
    out = tmp_path / 'campaign'
    result = tethersim('sweep', str(spec), '--out', str(out), timeout=600)
    assert result.returncode == 0, result.stderr
    assert '4 of 4 runs recorded, 4 ok, 0 failed' in result.stdout
    assert 'sweep four: 4/4 done, 0 failed' in result.stderr
    table = pq.read_table(out / 'results.parquet').to_pylist()
    with open(out / 'results.csv', newline='') as file:
        assert [row['run'] for row in csv.DictReader(file)] == [row['run'] for row in table]
    assert [row['index'] for row in table] == [0, 1, 2, 3]
    assert [row['platform.profile'] for row in table] == ['hpr1', 'hpr3', 'hpr1', 'hpr3']
    assert len({row['platform.seed'] for row in table}) == 4
    assert all(row['status'] == 'ok' and row['attempts'] == 1 and row['reason'] is None for row in table)

    alone = []
    for row in table:
        run_dir = out / 'runs' / row['run']
        scene = run_dir / 'platform.yaml'
        assert row['command'] == f'tethersim run {scene} --out runs/rerun-{row["run"]}'
        alone.append(start_tethersim('run', str(scene), '--out', str(tmp_path / f'alone-{row["run"]}')))
        if len(alone) == 2 or row is table[-1]:
            for process in alone:
                process.communicate(timeout=300)
                assert process.returncode == 0
            alone = []
    for row in table:
        run_dir, solo = out / 'runs' / row['run'], tmp_path / f'alone-{row["run"]}'
        figures = run_figures(run_dir)
        assert 'tracking_rmse_heave' in figures and figures['exit_status'] == 0
        assert simulated(figures) == simulated(run_figures(solo))
        assert {key: row[key] for key in figures} == figures
        assert differing_topics(run_dir, solo) == []


def test_a_failing_run_is_retried_then_recorded_with_its_reason_and_keep_failed_keeps_it_whole(tmp_path):
    scene = tmp_path / 'crashing.yaml'
    scene.write_text('description: a talker that crashes when told\nduration: 2.0\nrate: max\nnodes:\n'
                     f'  talker:\n    script: {NODES / "talker_double.py"}\n    parameters: {{crash_at: 0.0}}\n')
    spec = write_spec(tmp_path / 'crash.yaml', description='one of two runs crashes', scene=str(scene),
                      grid={'talker.crash_at': [0.0, 0.5]}, retries=1)
    out = tmp_path / 'campaign'
    result = tethersim('sweep', str(spec), '--out', str(out), '--keep', 'failed', timeout=600)
    assert result.returncode == 1, result.stderr
    assert 'run-0001 failed (attempt 1 of 2): exit status 1: node talker died with exit status 3' in result.stderr
    assert 'run-0001 failed after 2 attempt(s)' in result.stderr
    ok, failed = pq.read_table(out / 'results.parquet').to_pylist()
    assert (ok['status'], ok['attempts'], ok['reason'], ok['exit_status']) == ('ok', 1, None, 0)
    assert (failed['status'], failed['attempts']) == ('failed', 2)
    assert failed['reason'].startswith('exit status 1: node talker died with exit status 3')
    assert failed['exit_status'] == 1 and failed['talker.crash_at'] == 0.5
    assert '2 of 2 runs recorded, 1 ok, 1 failed' in result.stdout
    assert sorted(path.name for path in (out / 'runs' / 'run-0000').iterdir()) == [
        'crashing.yaml', 'figures.json', 'summary.txt', 'tethersim.log']
    assert (out / 'runs' / 'run-0001' / 'bag' / 'bag_0.mcap').is_file()
    assert (out / 'runs' / 'run-0001' / 'logs' / 'talker.log').is_file()


def test_ctrl_c_stops_every_run_and_leaves_no_process_and_resume_runs_only_what_is_missing(tmp_path):
    spec = write_spec(tmp_path / 'three.yaml', description='three platform runs at real time', scene='platform',
                      count=3, set={'duration': 4.0, 'rate': 1.0}, random={'platform.seed': {'range': [1, 1000]}})
    out = tmp_path / 'campaign'
    sweep = start_tethersim('sweep', str(spec), '--out', str(out), '--workers', '1')
    watch = ProcessWatch(sweep.pid)
    deadline = time.monotonic() + 300
    while not ((out / 'rows' / 'run-0000.json').exists() and (out / 'runs' / 'run-0001' / 'logs').is_dir()):
        assert sweep.poll() is None, sweep.communicate()
        assert time.monotonic() < deadline, 'the first run did not finish and the second start within 300 s'
        time.sleep(0.2)
    sweep.send_signal(signal.SIGINT)
    stdout, stderr = sweep.communicate(timeout=300)
    assert sweep.returncode == 130, stderr
    assert 'interrupted; stopping 1 run(s) under way' in stderr
    assert '(interrupted: --resume runs the rest)' in stdout
    assert watch.left_behind() == []
    assert processes_of(out) == []
    assert [path.name for path in (out / 'rows').iterdir()] == ['run-0000.json']
    first = (out / 'rows' / 'run-0000.json').read_text()
    assert len(pq.read_table(out / 'results.parquet')) == 1

    refused = tethersim('sweep', str(spec), '--out', str(out), timeout=120)
    assert refused.returncode == 2
    assert refused.stderr.strip() == (f'tethersim: error: {out}: already holds a campaign; give --resume to finish it, '
                                      'or another --out')

    resumed = tethersim('sweep', str(spec), '--out', str(out), '--workers', '1', '--resume', timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert '1 of 3 runs already recorded' in resumed.stderr and 'running the 2 missing' in resumed.stderr
    assert 'sweep three: 2 runs of platform' in resumed.stderr
    assert (out / 'rows' / 'run-0000.json').read_text() == first
    rows = pq.read_table(out / 'results.parquet').to_pylist()
    assert [(row['run'], row['status']) for row in rows] == [('run-0000', 'ok'), ('run-0001', 'ok'), ('run-0002', 'ok')]
    assert json.loads(first)['platform.seed'] == rows[0]['platform.seed']
    assert run_figures(out / 'runs' / 'run-0001')['sim_time'] == 4.0



def test_a_run_whose_worker_is_killed_is_tried_again_and_its_processes_end(tmp_path):
    spec = write_spec(tmp_path / 'killed.yaml', description='one platform run at real time', scene='platform',
                      set={'duration': 4.0, 'rate': 1.0}, retries=1)
    out = tmp_path / 'campaign'
    sweep = start_tethersim('sweep', str(spec), '--out', str(out))
    watch = ProcessWatch(sweep.pid)
    run_dir = out / 'runs' / 'run-0000'
    deadline = time.monotonic() + 300
    while not (run_dir / 'graph.yaml').exists():  # the run is simulating
        assert sweep.poll() is None, sweep.communicate()
        assert time.monotonic() < deadline, 'the run did not start within 300 s'
        time.sleep(0.2)
    bringup = next(p for p in processes_of(run_dir) if 'tether_bringup' in p.cmdline() and 'run' in p.cmdline())
    worker = bringup.parent()
    worker.kill()
    stdout, stderr = sweep.communicate(timeout=600)
    assert sweep.returncode == 0, stderr
    assert 'run-0000 failed (attempt 1 of 2): WorkerCrashedError' in stderr
    row, = pq.read_table(out / 'results.parquet').to_pylist()
    assert (row['status'], row['attempts'], row['exit_status'], row['sim_time']) == ('ok', 2, 0, 4.0)
    assert not bringup.is_running()
    assert watch.left_behind() == []
