"""``tethersim bag info`` and ``tethersim bag export``: what a bag holds, and one topic as CSV.

Messages are decoded with ``rosbags``, learning every type (custom ones too) from the
definitions stored in the bag itself, so no ROS installation is needed to read a bag.
"""

from __future__ import annotations

import csv
import dataclasses
from pathlib import Path

import numpy as np
from rosbags.typesys import Stores
from rosbags.typesys import get_types_from_msg
from rosbags.typesys import get_typestore

from tether_bringup.bag_reader import Bag
from tether_bringup.bag_reader import read_bag
from tether_bringup.errors import BagError


def bag_summary_lines(path: str | Path) -> list[str]:
    """Return the lines of ``tethersim bag info``: topics, types, counts, rates, duration."""
    bag = read_bag(path)
    size = bag.path.stat().st_size
    state = 'finalized' if bag.complete else 'TRUNCATED (not finalized; read up to the last complete chunk)'
    lines = [
        f'bag: {bag.path} ({size / 2**20:.2f} MiB, {state})',
        f'duration: {bag.duration:.3f} s, {len(bag.messages)} messages, {len(bag.topics)} topics',
        f'{"topic":<28} {"type":<42} {"count":>7} {"rate Hz":>8}',
    ]
    for topic in sorted(bag.topics.values(), key=lambda t: t.name):
        span = ((topic.last_ns or 0) - (topic.first_ns or 0)) / 1e9
        rate = (topic.count - 1) / span if topic.count > 1 and span > 0 else 0.0
        lines.append(f'{topic.name:<28} {topic.type_name:<42} {topic.count:>7} {rate:8.1f}')
    return lines


def typestore_for(bag: Bag):
    """Return a rosbags typestore that knows every type whose definition the bag holds."""
    store = get_typestore(Stores.EMPTY)
    types = {}
    for topic in bag.topics.values():
        types.update(get_types_from_msg(topic.definition, topic.type_name))
    store.register(types)
    return store


def decoded_messages(path: str | Path, topic: str) -> list[tuple[int, object]]:
    """Return (log time ns, decoded message) of every message on ``topic``."""
    bag = read_bag(path, topics=[topic])
    if topic not in bag.topics:
        known = ', '.join(sorted(read_bag(path).topics)) or 'none'
        raise BagError(f'{bag.path}: no messages on topic {topic} (topics: {known})')
    store = typestore_for(bag)
    type_name = bag.topics[topic].type_name
    return [(m.log_time, store.deserialize_cdr(m.data, type_name)) for m in bag.messages]


def flatten(message: object, prefix: str = '') -> dict[str, object]:
    """Flatten a decoded message into ``field.sub[index]`` columns."""
    if dataclasses.is_dataclass(message):
        row: dict[str, object] = {}
        for field in dataclasses.fields(message):
            if field.name == '__msgtype__':
                continue
            row.update(flatten(getattr(message, field.name), f'{prefix}.{field.name}' if prefix else field.name))
        return row
    if isinstance(message, np.ndarray):
        return {f'{prefix}[{i}]': value.item() for i, value in enumerate(message.ravel())}
    if isinstance(message, (list, tuple)):
        row = {}
        for i, item in enumerate(message):
            row.update(flatten(item, f'{prefix}[{i}]'))
        return row
    return {prefix: message}


def export_csv(path: str | Path, topic: str, csv_path: str | Path) -> int:
    """Write one row per message of ``topic`` (log time first); return the row count."""
    rows = [{'log_time': log_time / 1e9, **flatten(message)} for log_time, message in decoded_messages(path, topic)]
    columns: list[str] = []
    for row in rows:
        columns.extend(key for key in row if key not in columns)
    csv_path = Path(csv_path)
    try:
        with open(csv_path, 'w', newline='') as handle:
            writer = csv.DictWriter(handle, fieldnames=columns)
            writer.writeheader()
            writer.writerows(rows)
    except OSError as error:
        raise BagError(f'{csv_path}: cannot write ({error.strerror})') from None
    return len(rows)
