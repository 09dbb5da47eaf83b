"""Concatenated ``ros2msg`` message definitions, as rosbag2 writes them into MCAP schemas.

The top-level ``.msg`` text comes first; then every type it depends on, depth first, each
preceded by a line of 80 ``=`` and a line ``MSG: pkg/Type`` (rosbag2's
``LocalMessageDefinitionSource``). The text is the installed ``.msg`` file itself, so the
units and frames written in its comments travel with the bag.

:func:`type_hash` reads a type's RIHS01 hash (REP-2011) from the type description
``.json`` that rosidl installs beside the ``.msg`` file.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from ament_index_python.packages import PackageNotFoundError
from ament_index_python.packages import get_package_share_directory

from tether_bringup.errors import BagError

PRIMITIVES = frozenset({
    'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16',
    'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring',
})
SEPARATOR = '=' * 80
_FIELD_TYPE = re.compile(r'^\s*([A-Za-z0-9_/]+)')


def msg_file(type_name: str) -> Path:
    """Return the installed ``.msg`` file of ``pkg/msg/Type`` (or ``pkg/Type``)."""
    package, _, name = _split(type_name)
    try:
        share = Path(get_package_share_directory(package))
    except PackageNotFoundError:
        raise BagError(f'message package {package!r} of type {type_name!r} is not installed') from None
    path = share / 'msg' / f'{name}.msg'
    if not path.is_file():
        raise BagError(f'no message definition {path} for type {type_name!r}')
    return path


def type_hash(type_name: str) -> str:
    """Return the ``RIHS01_<hex>`` hash of ``pkg/msg/Type`` from its installed type description."""
    package, _, name = _split(type_name)
    path = msg_file(type_name).with_suffix('.json')
    try:
        hashes = json.loads(path.read_text())['type_hashes']
    except (OSError, ValueError, KeyError, TypeError):
        raise BagError(f'no type description with hashes in {path} for type {type_name!r}') from None
    for entry in hashes:
        if entry.get('type_name') == f'{package}/msg/{name}':
            return entry['hash_string']
    raise BagError(f'{path} holds no hash of {package}/msg/{name}')


def dependencies(text: str, package: str) -> list[str]:
    """Return the ``pkg/Type`` names of the non-primitive fields of a ``.msg`` text, in order."""
    found: list[str] = []
    for line in text.splitlines():
        match = _FIELD_TYPE.match(line.split('#', 1)[0])
        if match is None or match.group(1) in PRIMITIVES:
            continue
        base = match.group(1)
        if base == 'Header':
            base = 'std_msgs/Header'
        elif '/' not in base:
            base = f'{package}/{base}'
        if base not in found:
            found.append(base)
    return found


def concatenated_definition(type_name: str) -> str:
    """Return the rosbag2-style concatenated definition of ``pkg/msg/Type``."""
    package, _, _ = _split(type_name)
    top = msg_file(type_name).read_text()
    parts = [top.rstrip('\n')]
    seen: set[str] = set()

    def visit(text: str, pkg: str) -> None:
        for dep in dependencies(text, pkg):
            if dep in seen:
                continue
            seen.add(dep)
            dep_text = msg_file(dep).read_text()
            parts.append(f'{SEPARATOR}\nMSG: {dep}\n{dep_text.rstrip(chr(10))}')
            visit(dep_text, dep.split('/')[0])

    visit(top, package)
    return '\n'.join(parts) + '\n'


def _split(type_name: str) -> tuple[str, str, str]:
    parts = type_name.split('/')
    if len(parts) == 3 and parts[1] == 'msg':
        return parts[0], 'msg', parts[2]
    if len(parts) == 2:
        return parts[0], 'msg', parts[1]
    raise BagError(f'not a message type name: {type_name!r}')
