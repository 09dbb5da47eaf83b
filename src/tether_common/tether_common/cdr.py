"""A ROS 2 message serialized to CDR by generated Python code: what rclpy's serialization gives.

The node group's publishers send what this module serializes
(:class:`tether_common.lockstep.GroupPublisher`). rclpy's ``publish`` of a message object
converts it to its C struct and Fast DDS serializes that; ``publish`` of serialized bytes
skips both. Publishing with two idle readers in the process and one reader in another
(this machine, the least of five sets of 2,000): a ``PoseStamped`` 41–48 µs of the
publishing thread as an object, 29–31 µs serialized here; a ``TetherState`` 58–60 µs
against 37–40 µs. The generated code takes 0.2–3 µs a message where
``rclpy.serialization.serialize_message`` takes 2.6–17 µs. The format is plain little-endian CDR (XCDR1, the encapsulation
``CDR_LE``): each primitive aligned to its own size from the start of the payload, a string
as its ``uint32`` length with the terminating NUL and its bytes, a sequence as its ``uint32``
count and its elements, a fixed array as its elements. Each class's function is generated
once as straight-line code: the fields of nested messages inlined, each run of fixed-size
fields one ``struct.pack``. After a string or sequence the offset is known only at run time,
so such a run's packer is chosen from eight, one per offset modulo 8.

:func:`serializer` raises :class:`NotImplementedError` for a field type the graph does not
use (``char``, wide strings, ``long double``); callers publish such a message as rclpy does.
"""

from __future__ import annotations

import struct
import sys
from collections.abc import Callable
from functools import cache
from typing import Any

from rosidl_parser.definition import AbstractGenericString
from rosidl_parser.definition import AbstractSequence
from rosidl_parser.definition import AbstractWString
from rosidl_parser.definition import Array
from rosidl_parser.definition import BasicType
from rosidl_parser.definition import NamespacedType

from tether_common.message_types import field_class

_ENCAPSULATION = b'\x00\x01\x00\x00'
_PRIMITIVES = {
    'float': 'f', 'double': 'd', 'boolean': '?', 'octet': 'c',
    'int8': 'b', 'uint8': 'B', 'int16': 'h', 'uint16': 'H',
    'int32': 'i', 'uint32': 'I', 'int64': 'q', 'uint64': 'Q',
}
_NUMERIC_ARRAYS = set(_PRIMITIVES) - {'boolean', 'octet'}

if sys.byteorder != 'little':
    raise ImportError('tether_common.cdr writes little-endian CDR from native buffers: this machine is big-endian')


def serialize(msg: Any) -> bytes:
    """``msg`` as CDR: the bytes ``rclpy.serialization.serialize_message`` gives, with its padding
    written 0 (rclpy leaves padding uninitialized) and no spare bytes at the end (rclpy's buffer
    may have some: it is sized from an estimate).
    """
    return serializer(type(msg))(msg)


@cache
def serializer(cls: type) -> Callable[[Any], bytes]:
    """The generated CDR serializer of one message class (raises NotImplementedError for a field
    type it does not write).
    """
    writer = _Writer(known=0)
    writer.lines.append('def serialize(m):')
    writer.lines.append(f'    parts = [{writer.constant(_ENCAPSULATION)}]')
    writer.message(cls, 'm')
    writer.flush()
    writer.lines.append("    return b''.join(parts)")
    return writer.build('serialize')


@cache
def _body(cls: type) -> Callable[[Any, list, int], int]:
    """The serializer of one element of a sequence of ``cls``: appends to ``parts`` from offset ``off``
    (bytes after the encapsulation), returns the offset after it.
    """
    writer = _Writer(known=None)
    writer.lines.append('def body(m, parts, off):')
    writer.message(cls, 'm')
    writer.flush()
    writer.go_dynamic()
    writer.lines.append('    return off')
    return writer.build('body')


class _Writer:
    """Generates the code of one serializer: ``parts`` collects the bytes, ``off`` is the offset at
    run time once a variable-length field has been written (``known`` is the offset while it is
    known when the code is generated).
    """

    def __init__(self, known: int | None) -> None:
        self.lines: list[str] = []
        self.namespace: dict[str, Any] = {}
        self.known = known
        self.pending: list[tuple[str, int, str]] = []

    def build(self, name: str) -> Callable:
        exec('\n'.join(self.lines), self.namespace)
        return self.namespace[name]

    def constant(self, value: Any) -> str:
        name = f'_k{len(self.namespace)}'
        self.namespace[name] = value
        return name

    def local(self, expression: str) -> str:
        name = f'_v{len(self.lines)}'
        self.lines.append(f'    {name} = {expression}')
        return name

    def fixed(self, code: str, expression: str, alignment: int | None = None) -> None:
        """A fixed-size field: ``code`` the struct format of one item, a primitive aligned to its
        size or ``Ns`` bytes aligned to ``alignment`` (a fixed array's element size).
        """
        self.pending.append((code, alignment or struct.calcsize(code), expression))

    def flush(self) -> None:
        """Write the pending run of fixed-size fields as one pack."""
        if not self.pending:
            return
        values = ', '.join(expression for _, _, expression in self.pending)
        if self.known is not None:
            packer = _packer(self.pending, self.known)
            self.lines.append(f'    parts.append({self.constant(packer)}.pack({values}))')
            self.known += packer.size
        else:
            packers = tuple(_packer(self.pending, residue) for residue in range(8))
            chosen = self.local(f'{self.constant(packers)}[off & 7]')
            self.lines.append(f'    parts.append({chosen}.pack({values}))')
            self.lines.append(f'    off += {chosen}.size')
        self.pending = []

    def go_dynamic(self) -> None:
        """Keep the offset at run time from here on."""
        if self.known is not None:
            self.lines.append(f'    off = {self.known}')
            self.known = None

    def variable(self, data: str, size: str) -> None:
        """Bytes ``data`` of run-time length ``size`` that need no alignment of their own."""
        self.flush()
        self.go_dynamic()
        self.lines.append(f'    parts.append({data})')
        self.lines.append(f'    off += {size}')

    def string(self, expression: str) -> None:
        encoded = self.local(f'{expression}.encode()')
        self.fixed('I', f'len({encoded}) + 1')
        self.variable(f"{encoded} + b'\\0'", f'len({encoded}) + 1')

    def message(self, cls: type, source: str) -> None:
        for slot, slot_type in zip(cls.__slots__, cls.SLOT_TYPES):
            self.field(slot_type, f'{source}.{slot}')

    def field(self, slot_type, expression: str) -> None:
        if isinstance(slot_type, NamespacedType):
            self.message(field_class(slot_type), self.local(expression))
        elif isinstance(slot_type, AbstractWString):
            raise NotImplementedError('wide strings')
        elif isinstance(slot_type, AbstractGenericString):
            self.string(expression)
        elif isinstance(slot_type, BasicType):
            self.fixed(_primitive(slot_type), expression)
        elif isinstance(slot_type, Array):
            self.array(slot_type.value_type, self.local(expression), slot_type.size)
        elif isinstance(slot_type, AbstractSequence):
            self.sequence(slot_type.value_type, self.local(expression))
        else:
            raise NotImplementedError(f'field type {type(slot_type).__name__}')

    def array(self, value_type, value: str, size: int) -> None:
        if isinstance(value_type, BasicType) and value_type.typename in _NUMERIC_ARRAYS:
            item = struct.calcsize(_primitive(value_type))
            self.fixed(f'{size * item}s', f'{value}.tobytes()', item)
            return
        for index in range(size):
            self.field(value_type, f'{value}[{index}]')

    def sequence(self, value_type, value: str) -> None:
        self.fixed('I', f'len({value})')
        if isinstance(value_type, BasicType) and value_type.typename in _NUMERIC_ARRAYS:
            item = struct.calcsize(_primitive(value_type))
            self.flush()
            self.go_dynamic()
            self.lines.append(f'    if {value}:')
            if item > 1:
                self.lines.append(f"        parts.append(b'\\0' * (-off & {item - 1}))")
                self.lines.append(f'        off += -off & {item - 1}')
            self.lines.append(f'        parts.append({value}.tobytes())')
            self.lines.append(f'        off += {item} * len({value})')
            return
        if isinstance(value_type, NamespacedType):
            element = self.constant(_body(field_class(value_type)))
            self.flush()
            self.go_dynamic()
            self.lines.append(f'    for _item in {value}:')
            self.lines.append(f'        off = {element}(_item, parts, off)')
            return
        if isinstance(value_type, AbstractGenericString) and not isinstance(value_type, AbstractWString):
            self.flush()
            self.go_dynamic()
            self.lines.append(f'    for _item in {value}:')
            self.lines.append("        parts.append(b'\\0' * (-off & 3))")
            self.lines.append('        off += -off & 3')
            self.lines.append("        _encoded = _item.encode()")
            self.lines.append(f"        parts.append({self.constant(struct.Struct('<I'))}.pack(len(_encoded) + 1))")
            self.lines.append("        parts.append(_encoded + b'\\0')")
            self.lines.append('        off += len(_encoded) + 5')
            return
        if isinstance(value_type, BasicType) and value_type.typename == 'boolean':
            self.flush()
            self.go_dynamic()
            self.lines.append(f'    parts.append(bytes({value}))')
            self.lines.append(f'    off += len({value})')
            return
        raise NotImplementedError(f'sequence of {getattr(value_type, "typename", type(value_type).__name__)}')


def _primitive(basic: BasicType) -> str:
    try:
        return _PRIMITIVES[basic.typename]
    except KeyError:
        raise NotImplementedError(f'primitive {basic.typename}') from None


def _packer(items: list[tuple[str, int, str]], start: int) -> struct.Struct:
    """One struct for a run of fixed-size items starting at offset ``start``, with CDR's padding."""
    fmt = ['<']
    offset = start
    for code, alignment, _ in items:
        pad = -offset % alignment
        if pad:
            fmt.append(f'{pad}x')
        fmt.append(code)
        offset += pad + struct.calcsize(code)
    return struct.Struct(''.join(fmt))
