"""The node group's recording stream: frames written to a pipe come out whole and in order."""

from __future__ import annotations

import os
import random
import threading

from tether_common.record_stream import ANNOUNCE
from tether_common.record_stream import ANNOUNCED
from tether_common.record_stream import MESSAGE
from tether_common.record_stream import StreamReader
from tether_common.record_stream import StreamWriter
from tether_common.record_stream import open_pipe


def _read_all(fd: int, chunk: int) -> tuple[list[tuple[int, int, bytes]], int]:
    reader = StreamReader()
    frames = []
    while data := os.read(fd, chunk):
        frames += reader.feed(data)
    os.close(fd)
    return frames, reader.pending


def test_frames_arrive_whole_and_in_order_through_a_pipe():
    rng = random.Random(3)
    messages = [(rng.randrange(2), rng.randbytes(rng.randrange(0, 5000))) for _ in range(2000)]
    read_fd, write_fd = open_pipe()
    result = {}
    # reads of 7 bytes split headers and payloads at every offset
    thread = threading.Thread(target=lambda: result.update(zip(('frames', 'pending'), _read_all(read_fd, 7))))
    thread.start()
    writer = StreamWriter(write_fd)
    ids = [writer.announce('/a', '/node_a'), writer.announce('/b', '/node_b'), writer.announce('/a', '/node_c')]
    writer.announced()
    for index, (topic_id, data) in enumerate(messages):
        writer.add(topic_id, data)
        if index % 13 == 0:
            writer.flush()
    writer.close()
    thread.join(30)
    assert ids == [0, 1, 0]
    frames = result['frames']
    assert frames[:4] == [(ANNOUNCE, 0, b'/a\n/node_a'), (ANNOUNCE, 1, b'/b\n/node_b'), (ANNOUNCE, 0, b'/a\n/node_c'),
                          (ANNOUNCED, 0, b'')]
    assert frames[4:] == [(MESSAGE, topic_id, data) for topic_id, data in messages]
    assert result['pending'] == 0


def test_a_cut_frame_is_held_back_and_counted():
    reader = StreamReader()
    writer_fd_read, writer_fd = os.pipe()
    writer = StreamWriter(writer_fd)
    writer.add(4, b'0123456789')
    writer.close()
    data = os.read(writer_fd_read, 100)
    os.close(writer_fd_read)
    assert reader.feed(data[:-3]) == []
    assert reader.pending == len(data) - 3
    assert reader.feed(data[-3:]) == [(MESSAGE, 4, b'0123456789')]
    assert reader.pending == 0


def test_a_writer_whose_reader_is_gone_drops_frames_instead_of_failing():
    read_fd, write_fd = os.pipe()
    os.close(read_fd)
    writer = StreamWriter(write_fd)
    writer.add(0, b'x' * 100)
    writer.flush()
    assert writer.broken
    writer.add(0, b'y')
    writer.close()
