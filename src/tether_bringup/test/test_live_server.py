"""The live server's wrapper of the recorder's bag: the bag is written as without it, and each message is offered once."""

from __future__ import annotations

import yaml
from mcap.reader import make_reader

from tether_bringup.bag_writer import BagWriter
from tether_bringup.bag_writer import QosRecord
from tether_bringup.live_server import LiveBag
from tether_bringup.live_server import LiveServer
from tether_bringup.live_server import live_lines

CLOCK = 'rosgraph_msgs/msg/Clock'


def _clock(sec: int) -> bytes:
    return b'\x00\x01\x00\x00' + sec.to_bytes(4, 'little') + bytes(4)


def _write(bag, count: int) -> None:
    bag.add_topic('/clock', CLOCK, [QosRecord(depth=1)])
    for sec in range(count):
        bag.write('/clock', _clock(sec), sec * 1_000_000_000)
    bag.close()


def _records(path):
    with open(path, 'rb') as stream:
        reader = make_reader(stream)
        return ([(schema.name, schema.encoding, schema.data) for schema in reader.get_summary().schemas.values()],
                [(channel.topic, message.log_time, message.data) for _, channel, message in reader.iter_messages()])


def test_live_bag_writes_the_same_bag_and_offers_each_message_once(tmp_path):
    _write(BagWriter(tmp_path / 'plain'), 5)
    stats = tmp_path / 'live.yaml'
    server = LiveServer('127.0.0.1', 0, str(stats))
    assert not stats.exists()            # announced only once the recorder has advertised every topic
    server.announce()
    assert yaml.safe_load(stats.read_text())['url'] == server.url
    _write(LiveBag(BagWriter(tmp_path / 'live'), server), 5)
    assert _records(tmp_path / 'live' / 'live_0.mcap') == _records(tmp_path / 'plain' / 'plain_0.mcap')
    written = yaml.safe_load(stats.read_text())
    assert (written['offered'], written['served'], written['dropped']) == (5, 5, 0)
    [line] = live_lines(stats)
    assert line.startswith(f'live view: served on {server.url}: 5 of 5 messages')


def test_live_lines_without_statistics(tmp_path):
    assert live_lines(tmp_path / 'missing.yaml') == []
