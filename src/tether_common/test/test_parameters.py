"""ParamSpec: the checks the scene validator and the nodes share."""

from __future__ import annotations

import math

import pytest

from tether_common.parameters import ParamSpec
from tether_common.parameters import spec_table


def test_float_range_accepts_inside_and_ints_and_rejects_outside():
    spec = ParamSpec('rate', 1.0, 'Real-time factor', '', 0.5, 10.0)
    assert spec.check(2.5) is None
    assert spec.check(3) is None
    assert spec.coerce(3) == 3.0 and isinstance(spec.coerce(3), float)
    assert spec.check(0.1) == 'expected a number in [0.5, 10], got 0.1'
    assert spec.check(math.nan) == 'expected a finite number, got nan'
    assert spec.check(True) == 'expected a number in [0.5, 10], got True'
    assert spec.check('fast') == "expected a number in [0.5, 10], got 'fast'"


def test_int_rejects_float_and_bool():
    spec = ParamSpec('seed', 1, 'Seed', low=0)
    assert spec.check(7) is None
    assert spec.check(7.5) is not None
    assert spec.check(False) is not None


def test_choices_and_lists():
    spec = ParamSpec('effects', ['drag'], 'Effects', choices=('drag', 'wind', 'damping'))
    assert spec.check(['drag', 'wind']) is None
    assert spec.check(['drag', 'lift']) == "expected a list of a string from {drag, wind, damping}, got 'lift'"
    assert spec.check('drag') is not None
    empty = ParamSpec('names', [], 'Names', item_type=str)
    assert empty.check([]) is None and empty.element_type is str


def test_choice_or_existing_file(tmp_path, monkeypatch):
    spec = ParamSpec('profile', 'still', 'Profile', choices=('still', 'boat'), file_suffix='.csv')
    (tmp_path / 'heave.csv').write_text('time,heave,roll,pitch\n')
    monkeypatch.chdir(tmp_path)
    assert spec.check('boat') is None
    assert spec.check('heave.csv') is None and spec.check(str(tmp_path / 'heave.csv')) is None
    assert spec.check('sway.csv') == 'file not found: sway.csv'
    assert spec.check('hpr9') == "expected a string from {still, boat} or an existing .csv file, got 'hpr9'"
    optional = ParamSpec('log', '', 'Log to replay', file_suffix='.jsonl')
    assert optional.check('') is None
    assert optional.check('x.txt') == "expected a string naming an existing .jsonl file, got 'x.txt'"


def test_empty_list_without_item_type_is_refused():
    with pytest.raises(ValueError, match='needs item_type'):
        _ = ParamSpec('x', [], 'x').element_type


def test_spec_table_refuses_duplicates():
    with pytest.raises(ValueError, match='specified twice'):
        spec_table((ParamSpec('a', 1, 'a'), ParamSpec('a', 2, 'b')))


def test_a_vector_has_its_defaults_length_and_other_lists_any():
    vector = ParamSpec('uav_position', [3.22, 0.0, 5.9], 'UAV attachment', 'm')
    assert vector.fixed_length == 3 and vector.check([1, 2, 3]) is None
    assert vector.check([3.22, 0.0]) == 'expected a list of 3 numbers (m), got 2: [3.22, 0.0]'
    assert vector.check([1.0, 2.0, 3.0, 4.0]) == 'expected a list of 3 numbers (m), got 4: [1.0, 2.0, 3.0, 4.0]'
    free = ParamSpec('weights', [1.0, 2.0], 'Any number of weights', length=0)
    assert free.fixed_length is None and free.check([1.0]) is None
    names = ParamSpec('exclude', ['/rosout'], 'Topics')
    assert names.fixed_length is None and names.check([]) is None
    pair = ParamSpec('pair', [], 'Two names', item_type=str, length=2)
    assert pair.check(['a']) == "expected a list of 2 strings, got 1: ['a']"
