"""Parameter specifications shared by a node and the scene validator.

A node's parameters are written once, as a tuple of :class:`ParamSpec` named ``PARAMETERS``,
in a module of its package that does not import rclpy, which the package registers under the
``tethersim.parameters`` entry points as ``<executable> = <module>``. The node
declares them with descriptors and ranges (:mod:`tether_common.ros_parameters`); the
bringup validates a scene's values against the same specification before anything starts.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib.metadata import EntryPoint
from pathlib import Path
from types import ModuleType
from typing import Any

from tether_common.node_entry_points import node_entry_points

ParamValue = bool | int | float | str | list

PARAMETERS_GROUP = 'tethersim.parameters'
"""The entry-point group where a package names each node's parameters module: ``<executable> = <module>``."""


@dataclass(frozen=True)
class ParamSpec:
    """One node parameter: name, default, unit, allowed range or choices.

    The type is the type of ``default``: bool, int, float, str, or a list of one of these
    (an empty list default needs ``item_type``). A string parameter with ``file_suffix``
    names an input file: besides one of ``choices`` (if any) or the empty string (if that is
    the default), a value ending in ``file_suffix`` must be an existing file, relative
    paths taken from the working directory the node and the bringup share.

    A list of numbers with a non-empty default is a vector of the default's length (a
    position, a moment of inertia): a value of another length is refused, as one of any
    length is with ``length=0``; ``length`` gives the length of another list.

    A parameter is ``read_only`` unless the node applies a new value while it runs: rclpy
    then refuses a run-time change of a value the node read once.
    """

    name: str
    default: ParamValue
    description: str
    unit: str = ''
    low: float | None = None
    high: float | None = None
    choices: tuple[str, ...] = ()
    item_type: type | None = None
    read_only: bool = True
    file_suffix: str = ''
    length: int | None = None
    extra: dict = field(default_factory=dict, compare=False)

    @property
    def kind(self) -> type:
        """The Python type a value must have (``list`` for arrays)."""
        return type(self.default)

    @property
    def element_type(self) -> type | None:
        """The type of an array's items, or None for scalars."""
        if not isinstance(self.default, list):
            return None
        if self.item_type is not None:
            return self.item_type
        if not self.default:
            raise ValueError(f'parameter {self.name}: an empty list default needs item_type')
        return type(self.default[0])

    @property
    def fixed_length(self) -> int | None:
        """The number of items a list value must have, or None for any number (see the class docstring)."""
        if self.length is not None:
            return self.length or None
        if isinstance(self.default, list) and self.default and self.element_type in (int, float):
            return len(self.default)
        return None

    def expected(self) -> str:
        """Describe the accepted values in a few words, for error messages."""
        kind = self.kind
        if kind is list:
            count = self.fixed_length
            text = (f'a list of {_type_name(self.element_type)}' if count is None else
                    f'a list of {count} {_PLURAL.get(self.element_type, str(self.element_type))}')
        else:
            text = _type_name(kind)
        if self.choices:
            text += ' from {' + ', '.join(self.choices) + '}'
        if self.file_suffix:
            text += (' or' if self.choices else ' naming') + f' an existing {self.file_suffix} file'
        if self.low is not None or self.high is not None:
            low = '-inf' if self.low is None else f'{self.low:g}'
            high = 'inf' if self.high is None else f'{self.high:g}'
            text += f' in [{low}, {high}]'
        if self.unit:
            text += f' ({self.unit})'
        return text

    def check(self, value: object) -> str | None:
        """Return why ``value`` is not acceptable, or None when it is."""
        if self.kind is list:
            if not isinstance(value, list):
                return f'expected {self.expected()}, got {value!r}'
            if self.fixed_length is not None and len(value) != self.fixed_length:
                return f'expected {self.expected()}, got {len(value)}: {value!r}'
            for item in value:
                reason = self._check_scalar(item, self.element_type)
                if reason:
                    return reason
            return None
        return self._check_scalar(value, self.kind)

    def coerce(self, value: Any) -> ParamValue:
        """Return ``value`` in the parameter's own type (an int given for a float)."""
        if self.kind is float and isinstance(value, int) and not isinstance(value, bool):
            return float(value)
        if self.kind is list and self.element_type is float:
            return [float(item) for item in value]
        return value

    def _check_scalar(self, value: Any, kind: Any) -> str | None:
        ok = isinstance(value, kind) and not (kind is not bool and isinstance(value, bool))
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            ok = True
        if not ok:
            return f'expected {self.expected()}, got {value!r}'
        if kind in (int, float):
            if not math.isfinite(value):
                return f'expected a finite number, got {value!r}'
            if self.low is not None and value < self.low or self.high is not None and value > self.high:
                return f'expected {self.expected()}, got {value!r}'
        if self.file_suffix and isinstance(value, str) and value not in self.choices:
            return self._check_file(value)
        if self.choices and value not in self.choices:
            return f'expected {self.expected()}, got {value!r}'
        return None

    def _check_file(self, value: str) -> str | None:
        if value == '' and self.default == '':
            return None
        if not value.endswith(self.file_suffix):
            return f'expected {self.expected()}, got {value!r}'
        if not Path(value).is_file():
            return f'file not found: {value}'
        return None


_PLURAL: dict[Any, str] = {bool: 'booleans', int: 'integers', float: 'numbers', str: 'strings'}


def _type_name(kind: Any) -> str:
    return {bool: 'a boolean', int: 'an integer', float: 'a number', str: 'a string'}.get(kind, str(kind))


def spec_table(specs: tuple[ParamSpec, ...]) -> dict[str, ParamSpec]:
    """Index specifications by name, refusing duplicates."""
    table: dict[str, ParamSpec] = {}
    for spec in specs:
        if spec.name in table:
            raise ValueError(f'parameter {spec.name} is specified twice')
        table[spec.name] = spec
    return table


def parameter_module(package: str, executable: str) -> ModuleType | None:
    """The module holding the ``PARAMETERS`` of ``package``'s ``executable`` (None for a node without one)."""
    entry = specified_nodes().get((package, executable))
    return entry.load() if entry is not None else None


def specified_nodes() -> Mapping[tuple[str, str], EntryPoint]:
    """Every registered parameters module's entry point, by (package, executable); nothing imported."""
    return node_entry_points(PARAMETERS_GROUP)
