"""Fixtures of the cross-package tests."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture
def scene_file(tmp_path):
    """Write a scene YAML into tmp_path and return its path."""
    def write(text: str, name: str = 'scene.yaml') -> Path:
        path = tmp_path / name
        path.write_text(text)
        return path
    return write
