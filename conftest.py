"""Session-wide check of the test suite: tests write only under pytest's temporary paths.

The checkout is listed before and after the session; a file or directory that appeared
outside the build products (``build``, ``install``, ``log``, the venv, caches) fails the
session and is named, so a test that forgets ``--out tmp_path`` cannot go unnoticed.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent
NOT_CHECKED = frozenset({'.git', '.venv', 'build', 'install', 'log', '__pycache__', '.pytest_cache',
                         '.mypy_cache', '.ruff_cache'})


def tree_listing(root: Path) -> set[str]:
    """Every path under ``root`` (relative, ``/``-separated), build products and caches left out."""
    found: set[str] = set()
    for directory, subdirectories, files in os.walk(root):
        subdirectories[:] = [d for d in subdirectories if d not in NOT_CHECKED and not d.endswith('.egg-info')]
        base = Path(directory).relative_to(root)
        found.update((base / name).as_posix() for name in (*subdirectories, *files))
    return found


def pytest_sessionstart(session: pytest.Session) -> None:
    session.config.stash[_BEFORE] = tree_listing(ROOT)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    before = session.config.stash.get(_BEFORE, None)
    if before is None:
        return
    written = sorted(tree_listing(ROOT) - before)
    if written:
        shown = ', '.join(written[:10]) + (f' and {len(written) - 10} more' if len(written) > 10 else '')
        print(f'\nthe test session wrote into the checkout {ROOT}: {shown}', flush=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


_BEFORE = pytest.StashKey[set]()
