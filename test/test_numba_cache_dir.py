"""The numba cache is keyed on every compiled source, so an edit never leaves stale machine code.

numba keys a cached function on its own file: a caller compiled against another file's
function keeps the old code after that file changes. ``tethersim-env`` names the cache
directory by a digest of the compiled sources (``tools/numba_cache_dir.py``).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / 'tools' / 'numba_cache_dir.py'

CALLER = '''from numba import njit

from demo.laws import shift


@njit(cache=True)
def doubled(x):
    return shift(x) * 2.0
'''
CALLEE = '''from numba import njit


@njit(cache=True)
def shift(x):
    return x + 1.0
'''


def _cache_dir(src: Path, root: Path) -> str:
    done = subprocess.run([sys.executable, str(TOOL), str(src), str(root)], capture_output=True, text=True, check=True)
    return done.stdout.strip()


def _tree(tmp_path: Path) -> Path:
    package = tmp_path / 'src' / 'demo' / 'demo'
    package.mkdir(parents=True)
    (package / '__init__.py').write_text('')
    (package / 'kernels.py').write_text(CALLER)
    (package / 'laws.py').write_text(CALLEE)
    (package / 'report.py').write_text('TITLE = "a module no compiled code reaches"\n')
    return tmp_path / 'src'


def _doubled(src: Path, cache: str) -> float:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(src / 'demo'))
    done = subprocess.run([sys.executable, '-c', 'from demo.kernels import doubled; print(doubled(1.0))'],
                          env=env, capture_output=True, text=True, check=True)
    return float(done.stdout)


def test_an_edit_to_a_called_kernel_file_changes_the_cache_and_the_result(tmp_path):
    src = _tree(tmp_path)
    first = _cache_dir(src, tmp_path / 'cache')
    assert _doubled(src, first) == 4.0
    (src / 'demo' / 'demo' / 'laws.py').write_text(CALLEE.replace('x + 1.0', 'x + 5.0'))
    # numba's own key: the caller's file is unchanged, so its cache still holds x + 1.0
    assert _doubled(src, first) == 4.0
    second = _cache_dir(src, tmp_path / 'cache')
    assert second != first
    assert _doubled(src, second) == 12.0


def test_an_edit_no_compiled_code_reaches_keeps_the_cache(tmp_path):
    src = _tree(tmp_path)
    first = _cache_dir(src, tmp_path / 'cache')
    (src / 'demo' / 'demo' / 'report.py').write_text('TITLE = "edited"\n')
    assert _cache_dir(src, tmp_path / 'cache') == first


def test_the_project_environment_uses_the_cache_of_this_checkouts_sources():
    assert os.environ.get('NUMBA_CACHE_DIR') == _cache_dir(ROOT / 'src', ROOT / '.cache' / 'numba')
