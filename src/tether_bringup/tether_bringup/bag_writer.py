"""A rosbag2-compatible MCAP writer that can take already-serialized CDR messages.

What the file holds follows rosbag2's MCAP storage plugin for ROS 2 Jazzy: ``ros2``
profile; one ``ros2msg`` schema per type with the concatenated definition; one ``cdr``
channel per topic with ``offered_qos_profiles`` (YAML, version 9 format) and
``topic_type_hash`` metadata; zstd chunks, each with the CRC of its content; the CRC of
the data section and of the summary; Statistics in the summary; a ``rosbag2`` metadata
record with the serialized BagMetadata (version 9). Beside the ``.mcap`` it writes the
``metadata.yaml`` rosbag2 keeps in a bag directory.

Chunks end at whole multiples of ``chunk_period`` seconds of log time (sim time in a run):
a message logged at or after the open chunk's boundary closes it first. One damaged chunk
so costs at most ``chunk_period`` of sim time (with the messages of earlier stamps written
into it late, at most the lockstep window's), and where chunks end depends on the stamps,
not on the machine's speed. The open chunk is also closed and flushed to disk at least
every ``flush_period`` seconds of wall time, so a recorder killed with SIGKILL loses at most
that much data and leaves a file whose complete chunks every MCAP reader can still read.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from dataclasses import field
from pathlib import Path

import yaml
from mcap.writer import CompressionType
from mcap.writer import Writer

from tether_bringup.msgdef import concatenated_definition
from tether_bringup.msgdef import type_hash as installed_type_hash

INFINITE = {'sec': 9223372036, 'nsec': 854775807}
ROS_DISTRO = 'jazzy'


@dataclass
class QosRecord:
    """One offered QoS profile in the words rosbag2 uses in its YAML (version 9)."""

    history: str = 'keep_last'
    depth: int = 10
    reliability: str = 'reliable'
    durability: str = 'volatile'
    deadline: dict = field(default_factory=lambda: dict(INFINITE))
    lifespan: dict = field(default_factory=lambda: dict(INFINITE))
    liveliness: str = 'automatic'
    liveliness_lease_duration: dict = field(default_factory=lambda: dict(INFINITE))
    avoid_ros_namespace_conventions: bool = False

    def as_dict(self) -> dict:
        """Return the profile as rosbag2's YAML mapping."""
        return dict(self.__dict__)


def dump_qos_profiles(profiles: list[QosRecord]) -> str:
    """Return the ``offered_qos_profiles`` YAML string of a channel."""
    return yaml.safe_dump([profile.as_dict() for profile in profiles], sort_keys=False).strip()


def load_qos_profiles(text: str) -> list[QosRecord]:
    """Parse an ``offered_qos_profiles`` YAML string (version 9 names or version 8 numbers)."""
    loaded = yaml.safe_load(text) or []
    names = {
        'history': {0: 'system_default', 1: 'keep_last', 2: 'keep_all', 3: 'unknown'},
        'reliability': {0: 'system_default', 1: 'reliable', 2: 'best_effort', 3: 'unknown'},
        'durability': {0: 'system_default', 1: 'transient_local', 2: 'volatile', 3: 'unknown'},
        'liveliness': {0: 'system_default', 1: 'automatic', 3: 'manual_by_topic', 4: 'unknown'},
    }
    profiles = []
    for item in loaded:
        record = QosRecord()
        for key, value in item.items():
            if key in names and isinstance(value, int):
                value = names[key].get(value, 'unknown')
            if hasattr(record, key):
                setattr(record, key, value)
        profiles.append(record)
    return profiles


@dataclass
class _Topic:
    name: str
    type_name: str
    qos: list[QosRecord]
    type_hash: str
    channel_id: int
    count: int = 0


class BagWriter:
    """Write one rosbag2-compatible MCAP file; see the module docstring for the layout."""

    def __init__(self, directory: str | Path, *, flush_period: float = 1.0, chunk_period: float = 1.0,
                 chunk_size: int = 4 * 1024 * 1024, file_name: str | None = None) -> None:
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.path = self.directory / (file_name or f'{self.directory.name}_0.mcap')
        self._stream = open(self.path, 'wb')
        self._writer = Writer(self._stream, chunk_size=chunk_size, compression=CompressionType.ZSTD,
                              enable_data_crcs=True)
        self._writer.start(profile='ros2', library='tethersim')
        self._schemas: dict[str, int] = {}
        self._topics: dict[str, _Topic] = {}
        self._flush_period = flush_period
        self._last_flush = time.monotonic()
        self._chunk_period_ns = round(chunk_period * 1e9)
        self._chunk_end_ns: int | None = None
        self._first_ns: int | None = None
        self._last_ns = 0
        self._closed = False

    @property
    def topics(self) -> dict[str, _Topic]:
        """Topics registered so far, by name."""
        return self._topics

    def add_topic(self, name: str, type_name: str, qos: list[QosRecord], type_hash: str = '',
                  definition: str | None = None) -> None:
        """Register a topic; its schema is ``definition`` or else the installed concatenated ``.msg`` one.

        ``type_hash`` is the publisher's RIHS01 hash; without one (``/clock``, subscribed
        before any publisher exists) the installed type description's hash is written.
        """
        if name in self._topics:
            return
        type_hash = type_hash or installed_type_hash(type_name)
        schema_id = self._schemas.get(type_name)
        if schema_id is None:
            text = concatenated_definition(type_name) if definition is None else definition
            schema_id = self._writer.register_schema(name=type_name, encoding='ros2msg', data=text.encode())
            self._schemas[type_name] = schema_id
        channel_id = self._writer.register_channel(
            topic=name, message_encoding='cdr', schema_id=schema_id,
            metadata={'offered_qos_profiles': dump_qos_profiles(qos), 'topic_type_hash': type_hash})
        self._topics[name] = _Topic(name, type_name, qos, type_hash, channel_id)

    def write(self, topic: str, data: bytes, log_time_ns: int, publish_time_ns: int | None = None) -> None:
        """Append one serialized message of a registered topic."""
        entry = self._topics[topic]
        if self._chunk_end_ns is None or log_time_ns >= self._chunk_end_ns:
            if self._chunk_end_ns is not None:
                self._writer.flush()
                self._last_flush = time.monotonic()
            self._chunk_end_ns = (log_time_ns // self._chunk_period_ns + 1) * self._chunk_period_ns
        self._writer.add_message(
            channel_id=entry.channel_id, log_time=log_time_ns, data=data,
            publish_time=log_time_ns if publish_time_ns is None else publish_time_ns, sequence=0)
        entry.count += 1
        if self._first_ns is None:
            self._first_ns = log_time_ns
        self._first_ns = min(self._first_ns, log_time_ns)
        self._last_ns = max(self._last_ns, log_time_ns)
        self.maybe_flush()

    def maybe_flush(self) -> None:
        """Close the open chunk and flush it to disk if ``flush_period`` has passed."""
        now = time.monotonic()
        if now - self._last_flush >= self._flush_period:
            self._writer.flush()
            self._last_flush = now

    def metadata(self) -> dict:
        """Return rosbag2's BagMetadata (version 9) for what has been written."""
        start = self._first_ns or 0
        duration = max(0, self._last_ns - start)
        total = sum(topic.count for topic in self._topics.values())
        return {'rosbag2_bagfile_information': {
            'version': 9,
            'storage_identifier': 'mcap',
            'duration': {'nanoseconds': duration},
            'starting_time': {'nanoseconds_since_epoch': start},
            'message_count': total,
            'topics_with_message_count': [
                {'topic_metadata': {
                    'name': topic.name,
                    'type': topic.type_name,
                    'serialization_format': 'cdr',
                    'offered_qos_profiles': [q.as_dict() for q in topic.qos],
                    'type_description_hash': topic.type_hash,
                }, 'message_count': topic.count}
                for topic in self._topics.values()],
            'compression_format': '',
            'compression_mode': '',
            'relative_file_paths': [self.path.name],
            'files': [{
                'path': self.path.name,
                'starting_time': {'nanoseconds_since_epoch': start},
                'duration': {'nanoseconds': duration},
                'message_count': total,
            }],
            'custom_data': {},
            'ros_distro': ROS_DISTRO,
        }}

    def close(self) -> None:
        """Finalize the file (summary, statistics, rosbag2 metadata) and write metadata.yaml."""
        if self._closed:
            return
        self._closed = True
        metadata = self.metadata()
        self._writer.add_metadata('rosbag2', {'serialized_metadata': yaml.safe_dump(metadata, sort_keys=False)})
        self._writer.finish()
        self._stream.close()
        (self.directory / 'metadata.yaml').write_text(yaml.safe_dump(metadata, sort_keys=False))
