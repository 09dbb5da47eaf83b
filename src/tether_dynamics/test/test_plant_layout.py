"""The kernels' flat arrays are named once (tether_dynamics.layout): the plant's st, fp and acc slot
constants are their layouts' offsets, without overlaps, and packing refuses a wrong field.
"""

from __future__ import annotations

import numpy as np
import pytest

from tether_dynamics import layout
from tether_dynamics.plant import fem_kernels as fk


def _slots(prefix: str) -> dict[str, int]:
    return {name: value for name, value in vars(fk).items()
            if name.startswith(prefix) and name.isupper() and isinstance(value, int) and name != f'{prefix}SIZE'}


@pytest.mark.parametrize('prefix', ['ST_', 'FP_', 'ACC_'])
def test_every_slot_is_its_fields_offset_and_the_size_covers_them(prefix: str) -> None:
    fields = getattr(fk, f'{prefix}FIELDS')
    named = {f'{prefix}{name.upper()}': offset for (name, _), offset in zip(fields, layout.offsets(fields))}
    assert _slots(prefix) == named
    ends = [offset + width for (_, width), offset in zip(fields, layout.offsets(fields))]
    assert ends == [*layout.offsets(fields)[1:], getattr(fk, f'{prefix}SIZE')]


def test_packing_refuses_a_missing_unknown_or_misshapen_field() -> None:
    values = {name: np.zeros(width) for name, width in fk.FP_FIELDS}
    with pytest.raises(ValueError, match=r"missing \['owed'\]"):
        layout.pack('fp', fk.FP_FIELDS, {k: v for k, v in values.items() if k != 'owed'})
    with pytest.raises(ValueError, match=r"unknown \['spin'\]"):
        layout.pack('fp', fk.FP_FIELDS, {**values, 'spin': 1.0})
    with pytest.raises(ValueError, match="'acc1' needs 3"):
        layout.pack('fp', fk.FP_FIELDS, {**values, 'acc1': 0.0})
    assert layout.pack('fp', fk.FP_FIELDS, values).shape == (fk.FP_SIZE,)
