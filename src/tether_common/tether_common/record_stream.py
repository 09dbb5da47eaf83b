"""The node group's recording stream: the CDR bytes of what its nodes publish, piped to the recorder.

A message published over DDS to a reader in another process costs the publishing thread
Fast DDS's write: the shared-memory send, the heartbeat, the wake-up of the reader's
process. The recorder is the only reader in another process of most of the node group's
topics, so the group hands it the bytes its publishers already serialized
(:mod:`tether_common.cdr`) through a pipe the bringup opened between the two processes,
and the recorder takes those topics from the pipe instead of subscribing to them
(``tether_bringup.recorder_node``). The topics stay on DDS for every other reader.

Frames, each a :data:`HEADER` (kind, topic id, payload length) and its payload:

* ``ANNOUNCE``: the topic id's topic and the fully qualified name of a node publishing it
  (UTF-8, the two joined by a newline); sent for each publisher when the group links its nodes;
* ``ANNOUNCED``: every publisher of the group has been announced (no payload);
* ``MESSAGE``: one message's CDR bytes, in the order the group published them.

The writer queues frames and writes them with one system call per :meth:`StreamWriter.flush`
(the group flushes after each executor callback). A write blocks while the pipe is full, so a
recorder that falls behind slows the group instead of losing messages.
"""

from __future__ import annotations

import fcntl
import os
import struct

HEADER = struct.Struct('<BHI')
"""kind (u8), topic id (u16), payload length in bytes (u32), little-endian."""
MESSAGE, ANNOUNCE, ANNOUNCED = 0, 1, 2
PIPE_SIZE = 1 << 20
"""Bytes the pipe holds before a write blocks: about 4 s of ``outdoor_flight``'s recorded messages."""


def open_pipe() -> tuple[int, int]:
    """A pipe (read end, write end) that holds :data:`PIPE_SIZE` bytes (less if the system caps it); neither
    end is inherited by child processes unless passed to them.
    """
    read_fd, write_fd = os.pipe()
    try:
        fcntl.fcntl(write_fd, fcntl.F_SETPIPE_SZ, PIPE_SIZE)
    except OSError:
        pass
    return read_fd, write_fd


class StreamWriter:
    """The group's end of the stream, on the write end ``fd`` of the pipe."""

    def __init__(self, fd: int) -> None:
        self._fd = fd
        self._ids: dict[str, int] = {}
        self._frames: list[bytes] = []
        self.broken = False
        """True once a write failed (the recorder is gone): later frames are dropped."""

    def announce(self, topic: str, node: str) -> int:
        """Announce that ``node`` publishes ``topic``; return the topic's id for :meth:`add`."""
        topic_id = self._ids.setdefault(topic, len(self._ids))
        payload = f'{topic}\n{node}'.encode()
        self._frames += (HEADER.pack(ANNOUNCE, topic_id, len(payload)), payload)
        return topic_id

    def announced(self) -> None:
        """Mark every publisher announced and write the announcements."""
        self._frames.append(HEADER.pack(ANNOUNCED, 0, 0))
        self.flush()

    def add(self, topic_id: int, data: bytes) -> None:
        """Queue one message's CDR bytes."""
        self._frames += (HEADER.pack(MESSAGE, topic_id, len(data)), data)

    def flush(self) -> None:
        """Write the queued frames (blocking while the pipe is full)."""
        if not self._frames:
            return
        view = memoryview(b''.join(self._frames))
        self._frames.clear()
        while view and not self.broken:
            try:
                view = view[os.write(self._fd, view):]
            except OSError:
                self.broken = True

    def close(self) -> None:
        """Write what is queued and close the write end: the recorder reads the end of the stream."""
        self.flush()
        os.close(self._fd)


class StreamReader:
    """The recorder's end: splits the bytes read from the pipe into frames."""

    def __init__(self) -> None:
        self._buffer = bytearray()

    def feed(self, data: bytes) -> list[tuple[int, int, bytes]]:
        """The complete frames (kind, topic id, payload) that ``data`` ends, in order."""
        buffer = self._buffer
        buffer += data
        frames = []
        start, size, header = 0, len(buffer), HEADER.size
        while size - start >= header:
            kind, topic_id, length = HEADER.unpack_from(buffer, start)
            end = start + header + length
            if end > size:
                break
            frames.append((kind, topic_id, bytes(buffer[start + header:end])))
            start = end
        del buffer[:start]
        return frames

    @property
    def pending(self) -> int:
        """Bytes of an incomplete frame held back (non-zero at the end of the stream: a frame was cut)."""
        return len(self._buffer)
