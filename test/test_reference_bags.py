"""The reference recordings in bags/ decode with both readers and match the installed messages."""

from __future__ import annotations

from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

from tether_bringup.bag_reader import read_bag
from tether_bringup.msgdef import concatenated_definition

BAGS = sorted(p for p in (Path(__file__).resolve().parent.parent / 'bags').iterdir() if p.is_dir())


@pytest.mark.parametrize('bag_dir', BAGS, ids=[p.name for p in BAGS])
def test_reference_bag_decodes_and_matches_installed_definitions(bag_dir):
    bag = read_bag(bag_dir)
    assert bag.complete
    for topic in bag.topics.values():
        assert topic.definition == concatenated_definition(topic.type_name), (
            f'{topic.type_name} changed since {bag_dir.name} was recorded: record it again (bags/README.md)')
    with AnyReader([bag_dir]) as reader:
        rosbags_count = sum(1 for connection, _, raw in reader.messages()
                            if reader.deserialize(raw, connection.msgtype) is not None)
    with open(bag.path, 'rb') as stream:
        mcap_count = sum(1 for _ in make_reader(stream, decoder_factories=[DecoderFactory()]).iter_decoded_messages())
    assert rosbags_count == mcap_count == len(bag.messages) > 0
