"""Read a serialized message's sim-time stamp straight from its CDR bytes.

The recorder logs each message at its stamp, not at the time it happened to arrive, so a
bag's timing does not depend on CPU load. Three layouts carry a stamp at a fixed offset
after the 4-byte encapsulation header (XCDR1, either byte order):

* a first field ``std_msgs/Header`` (stamp first) or ``builtin_interfaces/Time``
  (``rosgraph_msgs/Clock``): sec at offset 4, nanosec at 8;
* a first field that is a sequence of such messages (``tf2_msgs/TFMessage``,
  ``visualization_msgs/MarkerArray``): the length at 4, the first element's stamp at 8
  (no stamp when the sequence is empty).
"""

from __future__ import annotations

import struct
from collections.abc import Callable

from tether_common.message_types import message_class

NS = 1_000_000_000
_STAMPED = ('std_msgs/Header', 'builtin_interfaces/Time')
_LITTLE = struct.Struct('<iI')
_BIG = struct.Struct('>iI')
_LITTLE_COUNT = struct.Struct('<I')
_BIG_COUNT = struct.Struct('>I')


def _first_field_type(msg_class) -> str:
    fields = msg_class.get_fields_and_field_types()
    return next(iter(fields.values()), '')


def _read_at(data: bytes, offset: int) -> int:
    sec, nanosec = (_LITTLE if data[1] else _BIG).unpack_from(data, offset)
    return sec * NS + nanosec


def _header_stamp(data: bytes) -> int:
    return _read_at(data, 4)


def _first_element_stamp(data: bytes) -> int | None:
    (count,) = (_LITTLE_COUNT if data[1] else _BIG_COUNT).unpack_from(data, 4)
    return _read_at(data, 8) if count else None


def stamp_reader(type_name: str) -> Callable[[bytes], int | None] | None:
    """A function returning the stamp (ns) of a serialized ``type_name``, or None if the type has none."""
    first = _first_field_type(message_class(type_name))
    if first in _STAMPED:
        return _header_stamp
    if first.startswith('sequence<') and first.endswith('>'):
        element = first[len('sequence<'):-1].split(',')[0]
        if '/' in element and _first_field_type(message_class(element)) in _STAMPED:
            return _first_element_stamp
    return None
