"""Named layouts of the flat arrays the compiled tether kernels take (parameters, state, accumulators).

Compiled code reads its parameters from flat arrays by slot; a layout names each slot once, as
``(name, width)`` pairs in order, and everything else is derived from it: the slot offsets the
kernels index with (module constants, which numba freezes into the cached code), the array's size,
and the packing by name that refuses a missing or unknown field. Both engines use it
(:mod:`tether_dynamics.fem.kernels`, :mod:`tether_dynamics.plant.fem_kernels`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

Layout = tuple[tuple[str, int], ...]


def scalars(*names: str) -> Layout:
    """A layout of one-wide fields."""
    return tuple((name, 1) for name in names)


def offsets(layout: Layout) -> tuple[int, ...]:
    """Each field's first slot, in the layout's order."""
    return tuple(int(i) for i in np.cumsum([0] + [width for _, width in layout])[:-1])


def size(layout: Layout) -> int:
    """Slots the layout takes."""
    return sum(width for _, width in layout)


def check_names(kind: str, names: tuple[str, ...], given: Mapping[str, object]) -> None:
    """ValueError naming the array ``kind`` unless ``given`` has exactly the fields ``names``."""
    missing = [n for n in names if n not in given]
    unknown = [n for n in given if n not in names]
    if missing or unknown:
        msg = f'{kind} layout mismatch: missing {missing}, unknown {unknown}'
        raise ValueError(msg)


def pack(kind: str, layout: Layout, values: Mapping[str, object], dtype: type = float) -> np.ndarray:
    """The flat array of ``layout`` from its named ``values`` (a field of width w takes w values);
    ValueError naming the array ``kind`` and the fields that are missing, unknown or of the wrong width.
    """
    check_names(kind, tuple(name for name, _ in layout), values)
    parts = []
    for name, width in layout:
        value: np.ndarray = np.atleast_1d(np.asarray(values[name], dtype))
        if value.shape != (width,):
            msg = f'{kind} field {name!r} needs {width} value(s), got shape {value.shape}'
            raise ValueError(msg)
        parts.append(value)
    return np.concatenate(parts)
