"""BagWriter: a rosbag2-compatible MCAP written from serialized messages reads back equal."""

from __future__ import annotations

import zlib

import pytest
import rclpy
import yaml
from mcap.reader import make_reader
from mcap.records import DataEnd
from mcap.records import Footer
from mcap.stream_reader import StreamReader
from rclpy.serialization import serialize_message
from rosbags.highlevel import AnyReader

from geometry_msgs.msg import PointStamped
from rosgraph_msgs.msg import Clock
from tether_bringup.bag_reader import read_bag
from tether_bringup.bag_writer import BagWriter
from tether_bringup.errors import BagError
from tether_bringup.bag_writer import QosRecord
from tether_bringup.bag_writer import dump_qos_profiles
from tether_bringup.bag_writer import load_qos_profiles
from tether_bringup.recorder_node import type_hash_string
from tether_msgs.msg import ReelState


def test_qos_yaml_round_trip_and_version_8_numbers():
    profiles = [QosRecord(reliability='best_effort', depth=5), QosRecord(durability='transient_local')]
    text = dump_qos_profiles(profiles)
    assert yaml.safe_load(text)[0]['reliability'] == 'best_effort'
    assert load_qos_profiles(text) == profiles
    legacy = load_qos_profiles('- {history: 1, depth: 5, reliability: 2, durability: 1}')
    assert (legacy[0].reliability, legacy[0].durability) == ('best_effort', 'transient_local')


def test_written_messages_read_back_with_rosbags_and_reader(tmp_path):
    writer = BagWriter(tmp_path / 'bag', flush_period=0.0)
    writer.add_topic('/reel/state', 'tether_msgs/msg/ReelState', [QosRecord()])
    writer.add_topic('/point', 'geometry_msgs/msg/PointStamped', [QosRecord(reliability='best_effort')])
    for i in range(20):
        state = ReelState(deployed_length=1.0 + i, mode=ReelState.MODE_CATENARY)
        state.header.stamp.sec = i
        writer.write('/reel/state', serialize_message(state), i * 10**9)
        point = PointStamped()
        point.point.x = -float(i)
        writer.write('/point', serialize_message(point), i * 10**9 + 5)
    writer.close()

    bag = read_bag(tmp_path / 'bag')
    assert bag.complete
    assert bag.topics['/reel/state'].count == 20
    assert bag.topics['/point'].qos[0].reliability == 'best_effort'
    assert bag.duration == 19.000000005
    with AnyReader([tmp_path / 'bag']) as reader:
        lengths = [reader.deserialize(raw, c.msgtype).deployed_length
                   for c, _, raw in reader.messages() if c.topic == '/reel/state']
    assert lengths == [1.0 + i for i in range(20)]
    assert [m.deployed_length for _, m in bag.decoded('/reel/state', required=False)] == lengths
    assert bag.decoded('/absent', required=False) == []
    with pytest.raises(BagError, match='no messages on topic /absent'):
        bag.decoded('/absent')
    metadata = yaml.safe_load((tmp_path / 'bag' / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    assert metadata['message_count'] == 40
    assert metadata['relative_file_paths'] == ['bag_0.mcap']


def test_unflushed_writer_leaves_readable_prefix(tmp_path):
    writer = BagWriter(tmp_path / 'bag', flush_period=1e9)
    writer.add_topic('/point', 'geometry_msgs/msg/PointStamped', [QosRecord()])
    for i in range(3):
        writer.write('/point', serialize_message(PointStamped()), i)
    writer._writer.flush()
    writer.write('/point', serialize_message(PointStamped()), 3)
    writer._stream.flush()
    bag = read_bag(tmp_path / 'bag', allow_damaged=True)
    assert not bag.complete
    assert bag.topics['/point'].count == 3


def test_every_channel_carries_the_type_hash_rclpy_reports(tmp_path, ros_context):
    """A topic registered without its publisher's hash (/clock) gets the installed type's
    RIHS01 hash, the same one rclpy reports for a publisher of that type.
    """
    node = rclpy.create_node('hash_probe', context=ros_context)
    node.create_publisher(Clock, '/clock', 1)
    node.create_publisher(ReelState, '/reel/state', 1)
    reported = {topic: type_hash_string(node.get_publishers_info_by_topic(topic)[0].topic_type_hash)
                for topic in ('/clock', '/reel/state')}
    node.destroy_node()
    writer = BagWriter(tmp_path / 'bag')
    writer.add_topic('/clock', 'rosgraph_msgs/msg/Clock', [QosRecord()])
    writer.add_topic('/reel/state', 'tether_msgs/msg/ReelState', [QosRecord()])
    writer.close()
    with open(tmp_path / 'bag' / 'bag_0.mcap', 'rb') as stream:
        channels = {c.topic: c.metadata['topic_type_hash'] for c in make_reader(stream).get_summary().channels.values()}
    assert reported['/clock'].startswith('RIHS01_')
    assert channels == reported
    metadata = yaml.safe_load((tmp_path / 'bag' / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    hashes = {t['topic_metadata']['name']: t['topic_metadata']['type_description_hash']
              for t in metadata['topics_with_message_count']}
    assert hashes == reported


def test_chunks_end_at_whole_chunk_periods_of_log_time(tmp_path):
    """One damaged chunk costs at most ``chunk_period`` of sim time, wherever the machine's flushes fall."""
    writer = BagWriter(tmp_path / 'bag', flush_period=1e9, chunk_period=0.5)
    writer.add_topic('/point', 'geometry_msgs/msg/PointStamped', [QosRecord()])
    for i in range(1, 31):
        writer.write('/point', serialize_message(PointStamped()), i * 10**8)
    writer.close()
    with open(writer.path, 'rb') as stream:
        summary = make_reader(stream).get_summary()
    ranges = [(chunk.message_start_time, chunk.message_end_time) for chunk in summary.chunk_indexes]
    assert ranges == [(10**8, 4 * 10**8)] + [(k * 5 * 10**8, k * 5 * 10**8 + 4 * 10**8) for k in range(1, 6)] + \
        [(30 * 10**8, 30 * 10**8)]
    assert read_bag(tmp_path / 'bag').chunks == 7
    with open(writer.path, 'rb') as stream:
        records = list(StreamReader(stream).records)
    data_end = next(record for record in records if isinstance(record, DataEnd))
    footer = next(record for record in records if isinstance(record, Footer))
    data_end_size = 1 + 8 + 4  # opcode, length, data_section_crc
    assert data_end.data_section_crc == zlib.crc32(writer.path.read_bytes()[:footer.summary_start - data_end_size])
