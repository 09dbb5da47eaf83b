"""The session check that fails a test run which wrote into the checkout."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

from tethersim_testing import ROOT


def test_listing_sees_new_paths_and_leaves_out_build_products(tmp_path):
    spec = importlib.util.spec_from_file_location('root_conftest', ROOT / 'conftest.py')
    guard = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(guard)
    (tmp_path / 'src').mkdir()
    before = guard.tree_listing(tmp_path)
    (tmp_path / 'runs' / 'fem-pendulum').mkdir(parents=True)
    (tmp_path / 'build' / 'x').mkdir(parents=True)
    (tmp_path / 'src' / '__pycache__').mkdir()
    assert sorted(guard.tree_listing(tmp_path) - before) == ['runs', 'runs/fem-pendulum']


def test_a_session_that_writes_into_the_checkout_fails(tmp_path):
    """A throw-away checkout with the guard and one test writing ``runs/``: the session fails."""
    (tmp_path / 'conftest.py').write_text((ROOT / 'conftest.py').read_text())
    (tmp_path / 'test_writes.py').write_text(
        'from pathlib import Path\n\n\ndef test_writes():\n'
        '    (Path(__file__).parent / "runs" / "catenary-analyze").mkdir(parents=True)\n')
    result = subprocess.run([sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider', '-c', '/dev/null',
                             '--rootdir', str(tmp_path), str(tmp_path)], capture_output=True, text=True, timeout=120,
                            cwd=tmp_path)
    assert result.returncode == 1, result.stdout
    assert '1 passed' in result.stdout
    assert f'the test session wrote into the checkout {tmp_path}: runs, runs/catenary-analyze' in result.stdout
