"""The plant kernels' parameter and state vectors (st, fp, acc) are named once, without overlaps."""

from __future__ import annotations

import pytest

from tether_dynamics.laws import AIR_FIELDS
from tether_dynamics.plant import fem_kernels as fk

WIDE = {'FP_ACC1': 3, 'FP_ACC_UAV': 3, 'FP_AIR': len(AIR_FIELDS)}


def _slots(prefix: str) -> dict[str, int]:
    return {name: value for name, value in vars(fk).items()
            if name.startswith(prefix) and name.isupper() and isinstance(value, int) and name != f'{prefix}SIZE'}


@pytest.mark.parametrize('prefix', ['ST_', 'FP_', 'ACC_'])
def test_every_slot_has_its_own_place_and_the_size_covers_them(prefix: str) -> None:
    slots = sorted(_slots(prefix).items(), key=lambda item: item[1])
    end = 0
    for name, offset in slots:
        assert offset == end, f'{name} at {offset}, the slot before it ends at {end}'
        end = offset + WIDE.get(name, 1)
    assert getattr(fk, f'{prefix}SIZE') == end
