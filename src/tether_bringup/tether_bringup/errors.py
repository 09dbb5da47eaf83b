"""Errors of the tethersim bringup: each carries a one-line message for the user."""

from __future__ import annotations


class TethersimError(Exception):
    """A user-facing error: printed as one line, exit status 2."""


class SceneError(TethersimError):
    """A scene file is missing, malformed, or names unknown keys or bad values."""


class BagError(TethersimError):
    """A bag is missing, unreadable or does not hold what was asked for."""


class RunError(TethersimError):
    """A run could not start or a node failed during it (exit status 1)."""

    exit_status = 1


class GraphConflictError(RunError):
    """The run's graph contradicts what was asked (a replayed topic the scene publishes too): exit status 2."""

    exit_status = 2


class RunDirectoryError(TethersimError):
    """The run directory cannot be used (it already holds a recording)."""
