"""The one way to read a bag: topics, messages and their decoding, also of a damaged file.

The file is walked record by record (:mod:`tether_bringup.mcap_scan`): every chunk is
decompressed and checked against its CRC, and so are the data section and the summary
where the file has their CRCs. A damaged bag (a chunk failing its CRC, a cut, damaged
framing or index) is refused with one line naming the first damaged place (byte offset,
the sim-time range and topics of a damaged chunk), unless damage is allowed: the caller
passes ``allow_damaged=True`` (``tethersim bag recover``, ``bag info``) or runs inside
:func:`damaged_bags_allowed` (the commands' ``--allow-damaged``). Then the bag yields
everything intact in it, with ``Bag.damage`` naming each damaged place and
:meth:`Bag.skipped_lines` saying what was skipped. Messages are decoded with
``rosbags``, learning every type (custom ones too) from the definitions stored in the bag,
so no ROS installation is needed to read one.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from dataclasses import field
from pathlib import Path
from typing import Any

import yaml
from rosbags.typesys import Stores
from rosbags.typesys import get_types_from_msg
from rosbags.typesys import get_typestore

from tether_bringup.bag_writer import QosRecord
from tether_bringup.bag_writer import load_qos_profiles
from tether_bringup.errors import BagError
from tether_bringup.mcap_scan import MAGIC
from tether_bringup.mcap_scan import Damage
from tether_bringup.mcap_scan import scan

ALLOW_OPTION = '--allow-damaged'
"""The option of every command that reads bags: read what is intact in a damaged bag and say what was skipped."""
_ALLOWED: ContextVar[list[Bag] | None] = ContextVar('damaged_bags_allowed', default=None)


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
    """Topics and messages of a bag, in log-time order, and the damage found reading it."""

    path: Path
    topics: dict[str, BagTopic] = field(default_factory=dict)
    messages: list[BagMessage] = field(default_factory=list)
    damage: list[Damage] = field(default_factory=list)
    chunks: int = 0
    crcs: set[str] = field(default_factory=set)
    """The CRCs the file has, all checked: ``chunk`` (every chunk's), ``data section``, ``summary``."""

    @property
    def complete(self) -> bool:
        """True for a finalized bag without damage."""
        return not self.damage

    @property
    def duration(self) -> float:
        """Seconds between the first and the last message."""
        if not self.messages:
            return 0.0
        return (self.messages[-1].log_time - self.messages[0].log_time) / 1e9

    def damage_line(self) -> str:
        """One line saying where and why the bag is damaged (empty for a complete bag)."""
        return _damage_line(self.damage)

    @property
    def lost_count(self) -> int | None:
        """Messages the damage cost, as the damaged chunks' indexes count them (None: not all are known)."""
        counts = [damage.lost_count for damage in self.damage]
        return None if None in counts else sum(c for c in counts if c is not None)

    def skipped_lines(self) -> list[str]:
        """What reading this damaged bag skipped: a line for the bag, one per damaged place."""
        if not self.damage:
            return []
        lost = self.lost_count
        count = 'an unknown number of' if lost is None else str(lost)
        lines = [f'DAMAGED bag {self.path}: read with {ALLOW_OPTION}: {len(self.messages)} intact messages used, '
                 f'{count} skipped at {len(self.damage)} damaged place(s):']
        return lines + [f'  skipped at {damage}' for damage in self.damage]

    def checked_line(self) -> str:
        """What reading the bag checked, in a few words: its chunks and messages, and its CRCs."""
        names = {'chunk': 'every chunk\'s CRC', 'data section': 'the data section\'s CRC', 'summary': 'the summary\'s CRC'}
        crcs = [text for key, text in names.items() if key in self.crcs]
        return (f'{self.chunks} chunks and {len(self.messages)} messages read, '
                + (', '.join(crcs) + ' checked' if crcs else 'the file has no CRCs to check'))

    def decoded(self, topic: str, required: bool = True) -> list[tuple[int, Any]]:
        """Return (log time ns, decoded message) of every message on ``topic``.

        A topic the bag does not have is an error, or no messages when not ``required``.
        """
        if topic not in self.topics:
            if not required:
                return []
            known = ', '.join(sorted(self.topics)) or 'none'
            raise BagError(f'{self.path}: no messages on topic {topic} (topics: {known})')
        entry = self.topics[topic]
        store = get_typestore(Stores.EMPTY)
        try:
            store.register(get_types_from_msg(entry.definition, entry.type_name))
        except Exception as error:  # rosbags raises its own parser errors for a bad definition
            raise BagError(f'{self.path}: the definition of {entry.type_name} in the bag cannot be parsed '
                           f'({error})') from None
        decoded = []
        for message in self.messages:
            if message.topic != topic:
                continue
            try:
                decoded.append((message.log_time, store.deserialize_cdr(message.data, entry.type_name)))
            except Exception as error:  # rosbags raises plain exceptions for malformed CDR
                raise BagError(f'{self.path}: a {topic} message at log time {message.log_time / 1e9:.3f} s '
                               f'does not decode as {entry.type_name} ({type(error).__name__})') from None
        return decoded


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


@contextmanager
def damaged_bags_allowed(allowed: bool = True) -> Iterator[list[Bag]]:
    """Within the block (if ``allowed``), :func:`read_bag` reads damaged bags; yields the list of those read."""
    damaged: list[Bag] = []
    token = _ALLOWED.set(damaged if allowed else None)
    try:
        yield damaged
    finally:
        _ALLOWED.reset(token)


def read_bag(path: str | Path, topics: list[str] | None = None, allow_damaged: bool = False) -> Bag:
    """Read every message of a bag (optionally only ``topics``); see the module docstring.

    Raises:
        BagError: no such bag, not an MCAP file, nothing in it is recoverable, or it is damaged
            and damage is not allowed.
    """
    file = resolve_bag(path)
    try:
        with open(file, 'rb') as stream:
            size = stream.seek(0, 2)
            stream.seek(0)
            head = stream.read(len(MAGIC))
            if head != MAGIC:
                if not head:
                    raise BagError(f'{file}: empty file: nothing to read')
                if MAGIC.startswith(head):
                    raise BagError(f'{file}: {size} bytes, cut inside the MCAP magic: nothing to read')
                raise BagError(f'{file}: not an MCAP file (it does not begin with the MCAP magic bytes)')
            scanned = scan(stream, size)
    except OSError as error:
        raise BagError(f'{file}: cannot read ({error.strerror})') from None
    if not scanned.channels and scanned.damage:
        raise BagError(f'{file}: {size} bytes, damaged before any topic was recorded: {scanned.damage[0]}')
    for damage in scanned.damage:
        damage.lost_topics = {scanned.channels[channel].topic if channel in scanned.channels else f'channel {channel}':
                              count for channel, count in damage.lost.items()}
    allowed = _ALLOWED.get()
    if scanned.damage and not allow_damaged and allowed is None:
        raise BagError(f'{file} is damaged at {_damage_line(scanned.damage)}; refused: {ALLOW_OPTION} reads '
                       'what is intact, `tethersim bag recover` rewrites it')
    bag = Bag(path=file, damage=scanned.damage, chunks=scanned.chunks, crcs=scanned.crcs)
    if scanned.damage and allowed is not None and not allow_damaged:
        allowed.append(bag)
    for message in scanned.messages:
        channel = scanned.channels.get(message.channel_id)
        if channel is None or (topics is not None and channel.topic not in topics):
            continue
        topic = bag.topics.get(channel.topic) or _topic(bag, channel, scanned.schemas.get(channel.schema_id))
        topic.count += 1
        topic.first_ns = message.log_time if topic.first_ns is None else min(topic.first_ns, message.log_time)
        topic.last_ns = message.log_time if topic.last_ns is None else max(topic.last_ns, message.log_time)
        bag.messages.append(BagMessage(channel.topic, message.log_time, message.publish_time, message.data))
    for channel in scanned.channels.values():
        if channel.topic not in bag.topics and (topics is None or channel.topic in topics):
            _topic(bag, channel, scanned.schemas.get(channel.schema_id))
    bag.messages.sort(key=lambda message: message.log_time)
    return bag


def _damage_line(damage: list[Damage]) -> str:
    if not damage:
        return ''
    more = f' (and {len(damage) - 1} more damaged place(s))' if len(damage) > 1 else ''
    return f'{damage[0]}{more}'


def _topic(bag: Bag, channel, schema) -> BagTopic:
    try:
        qos = load_qos_profiles(channel.metadata.get('offered_qos_profiles', ''))
    except (yaml.YAMLError, AttributeError, TypeError):  # a damaged QoS string: keep the default profile
        qos = [QosRecord()]
    topic = BagTopic(name=channel.topic, type_name=schema.name if schema else '', qos=qos,
                     type_hash=channel.metadata.get('topic_type_hash', ''),
                     definition=schema.data.decode(errors='replace') if schema else '')
    bag.topics[channel.topic] = topic
    return topic
