"""``tethersim bag info`` and ``tethersim bag export``: what a bag holds, and one topic as CSV."""

from __future__ import annotations

import csv
import dataclasses
from pathlib import Path

import numpy as np

from tether_bringup.bag_reader import Bag
from tether_bringup.bag_reader import read_bag
from tether_bringup.errors import BagError


def bag_summary_lines(path: str | Path, check: bool = False) -> list[str]:
    """Return the lines of ``tethersim bag info``: topics, types, counts, rates, duration, damage."""
    return describe_bag(read_for_info(path, check), check)


def read_for_info(path: str | Path, check: bool = False) -> Bag:
    """Read a bag for ``bag info``, damaged or not.

    Every chunk is read and checked against its CRC (:mod:`tether_bringup.bag_reader`). With
    ``check`` (``bag info --check``) every message is also decoded with its topic's definition.

    Raises:
        BagError: nothing in the file is readable; with ``check``, a message does not decode.
    """
    bag = read_bag(path, allow_damaged=True)
    if check:
        for topic in bag.topics:
            bag.decoded(topic)
    return bag


def describe_bag(bag: Bag, check: bool = False) -> list[str]:
    """The lines of :func:`bag_summary_lines` for a bag already read: a damaged bag's last line names its first
    damaged place, or with ``check`` every damaged place has a line.
    """
    size = bag.path.stat().st_size
    state = 'finalized' if bag.complete else 'DAMAGED: read everything intact (tethersim bag recover writes a finalized copy)'
    lines = [
        f'bag: {bag.path} ({size / 2**20:.2f} MiB, {state})',
        f'duration: {bag.duration:.3f} s, {len(bag.messages)} messages, {len(bag.topics)} topics',
        f'{"topic":<28} {"type":<42} {"count":>7} {"rate Hz":>8}',
    ]
    for topic in sorted(bag.topics.values(), key=lambda t: t.name):
        span = ((topic.last_ns or 0) - (topic.first_ns or 0)) / 1e9
        rate = (topic.count - 1) / span if topic.count > 1 and span > 0 else 0.0
        lines.append(f'{topic.name:<28} {topic.type_name:<42} {topic.count:>7} {rate:8.1f}')
    if check:
        lines.append(f'checked: {bag.checked_line()}, every message decoded')
        lines += [f'damaged at {damage}' for damage in bag.damage]
    elif not bag.complete:
        lines.append(f'damaged at {bag.damage_line()}')
    return lines


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
    rows = [{'log_time': log_time / 1e9, **flatten(message)} for log_time, message in read_bag(path).decoded(topic)]
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
