"""Walk an MCAP file record by record, keeping everything intact and naming what is damaged.

The MCAP readers stop with an exception at the first damaged byte. This walk reads the
file linearly with every length checked against the bytes that are left, every chunk
decompressed and checked against its CRC and size, every MessageIndex checked against the
chunk before it, the data section and summary CRCs checked where the file has them (the
data section's named only when no damage in it was found otherwise), and the closing magic
checked. A damaged chunk whose frame is intact is skipped and the walk
goes on; damage to the record framing (a cut, a damaged length or opcode) ends it. What
was read before and around the damage is returned with one description per damaged place;
a skipped chunk's description holds its time range and, from the MessageIndex records that
follow it, how many messages of each channel it held.

Record layout: MCAP specification, https://mcap.dev/spec (opcodes, Chunk, Footer CRCs).
"""

from __future__ import annotations

import io
import struct
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from dataclasses import field
from typing import BinaryIO

import zstandard
from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.opcode import Opcode
from mcap.records import Channel
from mcap.records import Chunk
from mcap.records import DataEnd
from mcap.records import Footer
from mcap.records import McapRecord
from mcap.records import Message
from mcap.records import MessageIndex
from mcap.records import Schema

MAGIC = b'\x89MCAP0\r\n'
RECORD_HEADER = struct.Struct('<BQ')
MESSAGE_PREFIX = 22  # channel id (2), sequence (4), log time (8), publish time (8)
FOOTER_CRC_SPAN = 16  # summary_start and summary_offset_start precede summary_crc in the Footer
PARSE_ERRORS = (struct.error, McapError, ValueError, EOFError, MemoryError)


@dataclass
class Damage:
    """One damaged place of a file: its byte offset and what is wrong there.

    For a chunk whose messages were skipped: ``lost``, the messages of each channel id it
    held that were not read (from the MessageIndex records after it), and ``lost_topics``,
    the same by topic name once the channels are known. ``unknown`` says why the messages
    lost there cannot be counted (a chunk no index follows, a file cut short), if so.
    """

    offset: int
    reason: str
    lost: dict[int, int] = field(default_factory=dict)
    lost_topics: dict[str, int] = field(default_factory=dict)
    unknown: str = ''

    @property
    def lost_count(self) -> int | None:
        """Messages the damaged place cost (0 if none), or None if that is unknown."""
        return None if self.unknown else sum(self.lost.values())

    def __str__(self) -> str:
        text = f'byte {self.offset}: {self.reason}'
        if self.unknown:
            return f'{text} (messages lost: unknown, {self.unknown})'
        if not self.lost_count:
            return text
        held = self.lost_topics or {f'channel {channel}': count for channel, count in self.lost.items()}
        return f'{text} ({self.lost_count} messages lost: ' + ', '.join(
            f'{topic} {count}' for topic, count in sorted(held.items()) if count) + ')'


@dataclass
class ScannedFile:
    """What the walk recovered: schemas, channels, messages in file order, damage found."""

    size: int
    chunks: int = 0
    crcs: set[str] = field(default_factory=set)
    """The CRCs the file has and the walk checked: ``chunk`` (every chunk has one), ``data section``, ``summary``."""
    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    messages: list[Message] = field(default_factory=list)
    damage: list[Damage] = field(default_factory=list)


class _Malformed(Exception):
    pass


def _name(opcode: int) -> str:
    try:
        return Opcode(opcode).name.title().replace('_', '')
    except ValueError:
        return f'record with opcode 0x{opcode:02x}'


_PARSERS: dict[int, Callable[[ReadDataStream, int], McapRecord]] = {
    Opcode.SCHEMA: lambda stream, _: Schema.read(stream),
    Opcode.CHANNEL: lambda stream, _: Channel.read(stream),
    Opcode.MESSAGE: Message.read,
    Opcode.CHUNK: lambda stream, _: Chunk.read(stream),
    Opcode.MESSAGE_INDEX: lambda stream, _: MessageIndex.read(stream),
    Opcode.DATA_END: lambda stream, _: DataEnd.read(stream),
    Opcode.FOOTER: lambda stream, _: Footer.read(stream),
}


def _parse(opcode: int, content: bytes) -> McapRecord:
    """Parse one record's content with the mcap library's record classes, or raise _Malformed."""
    if opcode == Opcode.MESSAGE and len(content) < MESSAGE_PREFIX:
        raise _Malformed(f'{len(content)} bytes, shorter than a message header')
    stream = ReadDataStream(io.BytesIO(content))
    try:
        record = _PARSERS[opcode](stream, len(content))
    except PARSE_ERRORS as error:
        raise _Malformed(str(error) or type(error).__name__) from None
    if stream.count > len(content) or (isinstance(record, Chunk) and stream.count != len(content)):
        raise _Malformed('its fields overrun the record')
    return record


def _decompress(chunk: Chunk) -> bytes:
    if chunk.compression == 'zstd':
        try:
            return zstandard.ZstdDecompressor().decompressobj().decompress(chunk.data)
        except zstandard.ZstdError as error:
            raise _Malformed(f'zstd data is corrupt ({error})') from None
    if chunk.compression == 'lz4':
        import lz4.frame
        try:
            return lz4.frame.decompress(chunk.data)
        except RuntimeError as error:
            raise _Malformed(f'lz4 data is corrupt ({error})') from None
    if chunk.compression == '':
        return chunk.data
    raise _Malformed(f'unknown compression {chunk.compression!r}')


def _time_range(start_ns: int, end_ns: int) -> str:
    """A chunk's log-time range: the sim time of what it holds in a tethersim bag (the recorder logs stamps)."""
    return f'sim time {start_ns / 1e9:.3f}-{end_ns / 1e9:.3f} s'


class _Walk:
    def __init__(self, stream: BinaryIO, size: int) -> None:
        self.stream = stream
        self.out = ScannedFile(size=size)
        self.crc = zlib.crc32(MAGIC)
        self.crc_before_record = self.crc
        self.summary_crc = 0
        self.data_end: int | None = None
        self.chunk_index: dict[int, list[tuple[int, int]]] | None = {}
        self.handlers: dict[int, Callable[[McapRecord, int], None]] = {
            Opcode.SCHEMA: self._schema, Opcode.CHANNEL: self._channel, Opcode.MESSAGE: self._message,
            Opcode.CHUNK: self._chunk, Opcode.MESSAGE_INDEX: self._message_index,
            Opcode.DATA_END: self._data_end, Opcode.FOOTER: self._footer,
        }
        self.summary_records: list[Schema | Channel] = []
        self.footer: Footer | None = None
        self.footer_offset = 0
        self.chunk_without_crc = False
        self.skipped: tuple[Damage, dict[int, int]] | None = None
        """The damaged chunk just walked and the messages of each channel read from it, until its MessageIndexes end."""

    def damaged(self, offset: int, reason: str, unknown: str = '') -> Damage:
        damage = Damage(offset, reason, unknown=unknown)
        self.out.damage.append(damage)
        return damage

    def ended(self, offset: int, reason: str) -> None:
        """Damage that ends the walk: what the data section held after it is lost, uncounted."""
        self.damaged(offset, reason, unknown='' if self.data_end is not None else
                     'the file is not readable after this byte')

    def chunk_damaged(self, offset: int, reason: str, read: dict[int, int]) -> None:
        """A chunk whose messages (all, or those not in ``read``) are skipped: count them from its MessageIndexes."""
        damage = self.damaged(offset, reason, unknown='no index follows the chunk')
        self.skipped = (damage, read)

    def run(self) -> None:
        size = self.out.size
        pos = len(MAGIC)
        while self.footer is None:
            header = self.stream.read(RECORD_HEADER.size)
            if not header:
                self.damaged(pos, 'the file ends here without a Footer: it was not finalized '
                                  '(the recorder was killed or the file was cut)',
                             unknown='' if self.data_end is not None else
                             'whatever was recorded after this byte is missing')
                return
            if len(header) < RECORD_HEADER.size:
                self.ended(pos, f'the file is cut inside a record header ({len(header)} of 9 bytes present)')
                return
            opcode, length = RECORD_HEADER.unpack(header)
            name = _name(opcode)
            if opcode < 0x80 and opcode not in Opcode.__members__.values():
                self.ended(pos, f'unknown record opcode 0x{opcode:02x}: the record framing is damaged')
                return
            remaining = size - pos - RECORD_HEADER.size
            if length > remaining:
                self.ended(pos, f'the {name} record begun here needs {length} bytes but the file ends '
                                f'{remaining} bytes later (cut short, or its length field is damaged)')
                return
            content = self.stream.read(length)
            self.crc_before_record = self.crc
            self.crc = zlib.crc32(content, zlib.crc32(header, self.crc))
            if self.data_end is not None:
                self.summary_crc = zlib.crc32(content if opcode != Opcode.FOOTER else content[:FOOTER_CRC_SPAN],
                                              zlib.crc32(header, self.summary_crc))
            if opcode != Opcode.MESSAGE_INDEX:
                self.skipped = None
            try:
                if opcode in self.handlers:
                    self.handlers[opcode](_parse(opcode, content), pos)
            except _Malformed as error:
                self.damaged(pos, f'malformed {name} record ({error}); skipped')
            pos += RECORD_HEADER.size + length
        self._close(pos)

    def _schema(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, Schema)
        if self.data_end is None:
            self.out.schemas.setdefault(record.id, record)
        else:
            self.summary_records.append(record)

    def _channel(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, Channel)
        if self.data_end is None:
            self.out.channels.setdefault(record.id, record)
        else:
            self.summary_records.append(record)

    def _message(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, Message)
        self.out.messages.append(record)

    def _chunk(self, chunk: McapRecord, pos: int) -> None:
        assert isinstance(chunk, Chunk)
        self.out.chunks += 1
        self.chunk_index = None
        where = _time_range(chunk.message_start_time, chunk.message_end_time)
        try:
            data = _decompress(chunk)
            if len(data) != chunk.uncompressed_size:
                raise _Malformed(f'{len(data)} bytes uncompressed, its header says {chunk.uncompressed_size}')
            if not chunk.uncompressed_crc:
                self.chunk_without_crc = True
            elif zlib.crc32(data) != chunk.uncompressed_crc:
                raise _Malformed('its content fails the CRC check')
        except _Malformed as error:
            self.chunk_damaged(pos, f'Chunk ({where}) is corrupt: {error}', {})
            return
        index: dict[int, list[tuple[int, int]]] = {}
        self.chunk_index = index
        inner = 0
        times = []
        while inner < len(data):
            if len(data) - inner < RECORD_HEADER.size:
                self.chunk_damaged(pos, f'Chunk ({where}) ends inside a record header; the rest of it is skipped',
                                   _counts(index))
                return
            opcode, length = RECORD_HEADER.unpack_from(data, inner)
            start = inner + RECORD_HEADER.size
            if length > len(data) - start:
                self.chunk_damaged(pos, f'Chunk ({where}) holds a {_name(opcode)} longer than the chunk; '
                                        'the rest of it is skipped', _counts(index))
                return
            if opcode in (Opcode.SCHEMA, Opcode.CHANNEL, Opcode.MESSAGE):
                record: McapRecord | None
                try:
                    record = _parse(opcode, data[start:start + length])
                except _Malformed as error:
                    self.damaged(pos, f'Chunk ({where}) holds a malformed {_name(opcode)} ({error}); skipped')
                    record = None
                if record is not None:
                    self.handlers[opcode](record, pos)
                if isinstance(record, Message):
                    index.setdefault(record.channel_id, []).append((record.log_time, inner))
                    times.append(record.log_time)
            inner = start + length
        if times and (min(times), max(times)) != (chunk.message_start_time, chunk.message_end_time):
            self.damaged(pos, f'Chunk ({where}) holds messages of {_time_range(min(times), max(times))}: '
                              'its time range is damaged')

    def _message_index(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, MessageIndex)
        if self.skipped is not None:
            damage, read = self.skipped
            damage.unknown = ''
            damage.lost[record.channel_id] = max(0, len(record.records) - read.get(record.channel_id, 0))
        if self.chunk_index is not None and sorted(record.records) != sorted(self.chunk_index.get(record.channel_id, [])):
            self.damaged(pos, f'MessageIndex of channel {record.channel_id} does not match the chunk before it')

    def _data_end(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, DataEnd)
        self.data_end = self.stream.tell()
        if record.data_section_crc:
            self.out.crcs.add('data section')
        if record.data_section_crc and record.data_section_crc != self.crc_before_record and not self.out.damage:
            self.damaged(pos, 'the data section fails its CRC check, though every chunk in it passes its own: '
                              'a record outside the chunks is damaged')

    def _footer(self, record: McapRecord, pos: int) -> None:
        assert isinstance(record, Footer)
        self.footer, self.footer_offset = record, pos
        if self.data_end is None:
            self.damaged(pos, 'Footer without a DataEnd record before it')
        elif record.summary_start not in (0, self.data_end):
            self.damaged(pos, f'the Footer places the summary at byte {record.summary_start}, '
                              f'it begins at byte {self.data_end}')
        elif record.summary_start and record.summary_crc and record.summary_crc != self.summary_crc:
            self.damaged(self.data_end, 'the summary section (the index readers use) fails its CRC check')
        else:
            if record.summary_start and record.summary_crc:
                self.out.crcs.add('summary')
            for summary_record in self.summary_records:
                table = self.out.schemas if isinstance(summary_record, Schema) else self.out.channels
                table.setdefault(summary_record.id, summary_record)  # type: ignore[arg-type]

    def _close(self, pos: int) -> None:
        tail = self.stream.read(len(MAGIC))
        if tail != MAGIC:
            self.damaged(pos, 'the file does not end with the MCAP magic after its Footer')
            return
        extra = self.out.size - pos - len(MAGIC)
        if extra:
            self.damaged(pos + len(MAGIC), f'{extra} bytes follow the end of the MCAP file')


def _counts(index: dict[int, list[tuple[int, int]]]) -> dict[int, int]:
    return {channel: len(entries) for channel, entries in index.items()}


def scan(stream: BinaryIO, size: int) -> ScannedFile:
    """Walk an MCAP file of ``size`` bytes whose 8 magic bytes ``stream`` has already yielded."""
    walk = _Walk(stream, size)
    walk.run()
    if walk.out.chunks and not walk.chunk_without_crc:
        walk.out.crcs.add('chunk')
    return walk.out
