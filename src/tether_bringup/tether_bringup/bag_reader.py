"""Read a bag written by the recorder (or by rosbag2), also one cut short by a crash.

A finalized file is read through its summary. A file without one (the recorder was
killed) is read linearly up to its last complete chunk and flagged as truncated.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field
from pathlib import Path

from mcap.exceptions import McapError
from mcap.reader import NonSeekingReader
from mcap.reader import make_reader

from tether_bringup.bag_writer import QosRecord
from tether_bringup.bag_writer import load_qos_profiles
from tether_bringup.errors import BagError


@dataclass
class BagMessage:
    """One serialized message of a bag."""

    topic: str
    log_time: int
    publish_time: int
    data: bytes


@dataclass
class BagTopic:
    """One topic of a bag."""

    name: str
    type_name: str
    qos: list[QosRecord]
    type_hash: str
    definition: str
    count: int = 0
    first_ns: int | None = None
    last_ns: int | None = None


@dataclass
class Bag:
    """Topics and messages of a bag, in log-time order."""

    path: Path
    topics: dict[str, BagTopic] = field(default_factory=dict)
    messages: list[BagMessage] = field(default_factory=list)
    complete: bool = True

    @property
    def duration(self) -> float:
        """Seconds between the first and the last message."""
        if not self.messages:
            return 0.0
        return (self.messages[-1].log_time - self.messages[0].log_time) / 1e9


def resolve_bag(path: str | Path) -> Path:
    """Find the ``.mcap`` file of a bag given as a file, a bag directory or a run directory."""
    path = Path(path)
    if path.is_file():
        return path
    if path.is_dir():
        for directory in (path, path / 'bag'):
            files = sorted(directory.glob('*.mcap'))
            if files:
                return files[0]
        raise BagError(f'{path}: no .mcap file in this directory or its bag/ directory')
    raise BagError(f'{path}: no such bag')


def read_bag(path: str | Path, topics: list[str] | None = None) -> Bag:
    """Read every message of a bag (optionally only ``topics``); see the module docstring."""
    file = resolve_bag(path)
    bag = Bag(path=file)
    with open(file, 'rb') as stream:
        try:
            reader = make_reader(stream)
            summary = reader.get_summary()
            records = reader.iter_messages(log_time_order=True) if summary is not None else None
            if records is not None:
                _collect(bag, records, topics)
                return bag
        except McapError:
            pass
        except (ValueError, OSError, EOFError) as error:
            raise BagError(f'{file}: not a readable MCAP file ({error})') from None
        stream.seek(0)
        bag.complete = False
        try:
            _collect(bag, NonSeekingReader(stream).iter_messages(log_time_order=False), topics)
        except McapError as error:
            if not bag.messages and not bag.topics:
                raise BagError(f'{file}: not a readable MCAP file ({error})') from None
        except (ValueError, EOFError) as error:
            if not bag.messages:
                raise BagError(f'{file}: not a readable MCAP file ({error})') from None
    bag.messages.sort(key=lambda message: message.log_time)
    return bag


def _collect(bag: Bag, records, topics: list[str] | None) -> None:
    for schema, channel, message in records:
        if topics is not None and channel.topic not in topics:
            continue
        topic = bag.topics.get(channel.topic)
        if topic is None:
            topic = BagTopic(
                name=channel.topic,
                type_name=schema.name if schema else '',
                qos=load_qos_profiles(channel.metadata.get('offered_qos_profiles', '')),
                type_hash=channel.metadata.get('topic_type_hash', ''),
                definition=schema.data.decode() if schema else '')
            bag.topics[channel.topic] = topic
        topic.count += 1
        topic.first_ns = message.log_time if topic.first_ns is None else topic.first_ns
        topic.last_ns = message.log_time
        bag.messages.append(BagMessage(channel.topic, message.log_time, message.publish_time, message.data))
