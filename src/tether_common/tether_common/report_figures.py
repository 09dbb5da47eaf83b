"""Figures of a scene report as data: beside the report's sentences, the numbers they state.

A scene report (``module:function`` in a scene's ``reports``) returns the lines of its text.
It may return a :class:`ReportLines` instead: those lines (it is a list of them, so every
caller of a report keeps working) and a flat mapping of figure names to scalars, which the
bringup writes to the run directory's ``figures.json`` and a campaign turns into a row of
its results table.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from collections.abc import Mapping

Scalar = bool | int | float | str | None
"""A figure's value: a number, a flag, a word (an outcome, a reason) or None for a figure not available."""


def scalar(value: object) -> Scalar:
    """``value`` as a plain Python scalar: numpy numbers to int/float/bool, a non-finite float to None.

    Raises:
        TypeError: ``value`` is not a scalar (a list, an array, a mapping).
    """
    if value is None or isinstance(value, (bool, str)):
        return value
    item = getattr(value, 'item', None)
    if item is not None and getattr(value, 'shape', ()) == ():
        value = item()
    if isinstance(value, bool):
        return value
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    raise TypeError(f'a report figure must be a scalar, got {type(value).__name__}')


class ReportLines(list):
    """The lines of a scene report (a ``list`` of ``str``) and its figures (``figures``: name -> scalar)."""

    def __init__(self, lines: Iterable[str], figures: Mapping[str, object]) -> None:
        super().__init__(lines)
        self.figures: dict[str, Scalar] = {str(name): scalar(value) for name, value in figures.items()}
