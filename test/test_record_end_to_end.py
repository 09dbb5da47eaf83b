"""End to end: a scene of several processes is run, recorded, and every message decoded.

The talker (test double) logs every message it publishes; the bag must hold all of them,
equal field by field, when decoded by rosbags (AnyReader, learning the custom types from
the bag) and by mcap + mcap-ros2-support. The file must carry rosbag2's layout.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import domain_coordinator
import pytest
import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

from tether_bringup.bag_info import flatten
from tether_bringup.bag_reader import read_bag
from tether_bringup.msgdef import type_hash

from tethersim_testing import SCENES
from tethersim_testing import processes_of
from tethersim_testing import tethersim
from tethersim_testing import write_scene


@pytest.fixture(scope='module')
def recorded(tmp_path_factory):
    run_dir = tmp_path_factory.mktemp('run')
    sent_log = run_dir / 'sent.jsonl'
    scene = yaml.safe_load((SCENES / 'talk_listen.yaml').read_text())
    scene['nodes']['talker']['parameters']['sent_log'] = str(sent_log)
    scene['nodes']['talker']['script'] = str(SCENES.parent / 'nodes' / 'talker_double.py')
    scene['nodes']['listener']['script'] = str(SCENES.parent / 'nodes' / 'listener_double.py')
    scene_path = write_scene(scene, run_dir / 'scene.yaml')
    result = tethersim('run', scene_path, '--out', str(run_dir / 'out'))
    sent = [json.loads(line) for line in sent_log.read_text().splitlines()]
    return result, run_dir / 'out', sent


def test_run_exits_cleanly_and_leaves_bag_and_summary(recorded):
    result, out, _ = recorded
    assert result.returncode == 0, result.stderr
    assert (out / 'bag' / 'bag_0.mcap').is_file()
    assert (out / 'bag' / 'metadata.yaml').is_file()
    summary = (out / 'summary.txt').read_text()
    simulated = summary.splitlines()[1].split()
    assert simulated[1] == simulated[4], summary  # simulated S s of D s: the whole duration ran
    for node in ('recorder', 'talker', 'listener'):
        assert any(line.split()[:2] == [node, '0'] for line in summary.splitlines()), summary
    assert not processes_of(out)


def test_summary_gives_each_process_cpu_per_simulated_second_and_their_total(recorded):
    _, out, _ = recorded
    lines = (out / 'summary.txt').read_text().splitlines()
    header = lines.index(next(line for line in lines if line.startswith('node ')))
    assert lines[header].split()[4:6] == ['cpu', 's/sim'], lines[header]
    rows = {}
    for line in lines[header + 1:]:
        fields = line.split()
        if fields[0] == 'total':
            total = float(fields[1])
            break
        rows[fields[0]] = (float(fields[2]), float(fields[3]))
    assert {'tethersim', 'recorder', 'talker', 'listener'} <= set(rows), lines
    simulated = float(lines[1].split()[1])
    for name, (cpu_s, per_sim_second) in rows.items():
        assert 0 <= per_sim_second * simulated <= cpu_s + 0.05, (name, lines)  # a part of the whole run's CPU
    assert total == pytest.approx(sum(rate for _, rate in rows.values()), abs=0.002 * len(rows))
    ceiling = lines[lines.index(next(line for line in lines if line.startswith('total'))) + 1]
    assert float(ceiling.split('allow at most ')[1].split('x')[0]) == pytest.approx((os.cpu_count() or 1) / total,
                                                                                    rel=0.01), ceiling
    busiest, main = ceiling.split('runs on one core at most: the busiest, ')[1].split(' CPU s per sim s')[0].split(' at ')
    assert 0 < float(main) <= rows[busiest][1] + 0.002, ceiling  # the main thread is a part of its process
    allows = float(ceiling.split(' allows ')[1].split('x')[0])
    assert allows == pytest.approx(1 / float(main), rel=0.02), ceiling
    assert float(ceiling.rpartition('ceiling ')[2].rstrip('x')) == pytest.approx(
        min((os.cpu_count() or 1) / total, allows), rel=0.01), ceiling
    machine = next(line for line in lines if line.startswith("the machine's"))
    split = dict(part.rsplit(' ', 1) for part in machine.split('(/proc/stat): ')[1].split(', '))
    assert list(split) == ['this run', 'other processes', 'idle', 'stolen by the hypervisor'], machine
    assert sum(int(share.rstrip('%')) for share in split.values()) == pytest.approx(100, abs=2), machine


def _by_topic(sent):
    topics = {}
    for entry in sent:
        topics.setdefault(entry['topic'], []).append(entry)
    return topics


def test_rosbags_decodes_every_published_message(recorded):
    _, out, sent = recorded
    expected = _by_topic(sent)
    with AnyReader([out / 'bag' / 'bag_0.mcap']) as reader:
        decoded = {}
        for connection, _, raw in reader.messages():
            decoded.setdefault(connection.topic, []).append(reader.deserialize(raw, connection.msgtype))
    estimates = decoded['/test/estimate']
    assert len(estimates) == len(expected['/test/estimate']) == 100
    for message, entry in zip(estimates, expected['/test/estimate']):
        assert message.header.stamp.sec * 10**9 + message.header.stamp.nanosec == entry['stamp']
        assert message.dz == entry['dz']
        assert message.dz_rate == entry['dz_rate']
        assert list(message.covariance) == entry['covariance']
        assert message.rejected == entry['rejected']
        assert message.rejection_reason == entry['rejection_reason']
    imus = decoded['/test/imu']
    assert [m.linear_acceleration.z for m in imus] == [e['az'] for e in expected['/test/imu']]
    assert [m.mode for m in decoded['/test/uav_state']] == ['GUIDED']
    echoes = decoded['/test/echo']
    assert [e.point.x for e in echoes] == [e['dz'] for e in expected['/test/estimate']]


def test_mcap_ros2_decodes_every_published_message(recorded):
    _, out, sent = recorded
    expected = _by_topic(sent)
    with open(out / 'bag' / 'bag_0.mcap', 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        decoded = {}
        for _, channel, _, message in reader.iter_decoded_messages():
            decoded.setdefault(channel.topic, []).append(message)
    assert [m.dz for m in decoded['/test/estimate']] == [e['dz'] for e in expected['/test/estimate']]
    assert [list(m.covariance) for m in decoded['/test/estimate']] == [e['covariance'] for e in expected['/test/estimate']]
    assert [m.linear_acceleration.z for m in decoded['/test/imu']] == [e['az'] for e in expected['/test/imu']]
    clock = [m.clock.sec + m.clock.nanosec * 1e-9 for m in decoded['/clock']]
    assert clock == sorted(clock) and clock[-1] == pytest.approx(2.0)


def test_file_has_rosbag2_layout(recorded):
    _, out, _ = recorded
    with open(out / 'bag' / 'bag_0.mcap', 'rb') as stream:
        reader = make_reader(stream)
        header = reader.get_header()
        summary = reader.get_summary()
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
    assert header.profile == 'ros2'
    assert summary.statistics.message_count > 0
    assert summary.chunk_indexes and all(c.compression == 'zstd' for c in summary.chunk_indexes)
    schemas = {s.name: s for s in summary.schemas.values()}
    assert schemas['tether_msgs/msg/RelativeEstimate'].encoding == 'ros2msg'
    definition = schemas['tether_msgs/msg/RelativeEstimate'].data.decode()
    assert '=' * 80 + '\nMSG: std_msgs/Header' in definition
    assert 'MSG: builtin_interfaces/Time' in definition
    channels = {c.topic: c for c in summary.channels.values()}
    for channel in channels.values():
        assert channel.message_encoding == 'cdr'
        assert channel.metadata['topic_type_hash'] == type_hash(summary.schemas[channel.schema_id].name)
    imu_qos = yaml.safe_load(channels['/test/imu'].metadata['offered_qos_profiles'])
    estimate_qos = yaml.safe_load(channels['/test/estimate'].metadata['offered_qos_profiles'])
    state_qos = yaml.safe_load(channels['/test/uav_state'].metadata['offered_qos_profiles'])
    assert imu_qos[0]['reliability'] == 'reliable'  # lockstep inputs must not be dropped
    assert estimate_qos[0]['reliability'] == 'reliable'
    assert state_qos[0]['durability'] == 'transient_local'
    bag_metadata = yaml.safe_load(metadata['rosbag2']['serialized_metadata'])['rosbag2_bagfile_information']
    assert bag_metadata['version'] == 9
    assert bag_metadata['storage_identifier'] == 'mcap'
    counts = {t['topic_metadata']['name']: t['message_count'] for t in bag_metadata['topics_with_message_count']}
    assert counts['/test/estimate'] == 100


def test_bag_info_and_csv_export(recorded, tmp_path):
    _, out, sent = recorded
    info = tethersim('bag', 'info', str(out))
    assert info.returncode == 0, info.stderr
    line = next(line for line in info.stdout.splitlines() if line.startswith('/test/estimate'))
    assert line.split()[1] == 'tether_msgs/msg/RelativeEstimate'
    assert int(line.split()[2]) == 100
    assert float(line.split()[3]) == pytest.approx(50.0, rel=0.02)
    csv_path = tmp_path / 'estimate.csv'
    export = tethersim('bag', 'export', str(out), '--topic', '/test/estimate', '--csv', str(csv_path))
    assert export.returncode == 0, export.stderr
    rows = csv_path.read_text().splitlines()
    header = rows[0].split(',')
    assert 'dz' in header and 'covariance[24]' in header and 'header.stamp.sec' in header
    assert len(rows) == 101
    first = dict(zip(header, rows[1].split(',')))
    assert float(first['dz']) == _by_topic(sent)['/test/estimate'][0]['dz']


def test_replay_republishes_equal_messages_and_records_node_under_test(recorded, tmp_path, scene_file):
    _, out, _ = recorded
    listener_only = scene_file(
        'description: the listener alone, as a node under test\n'
        'nodes:\n'
        f'  listener:\n    script: {Path(__file__).parent / "nodes" / "listener_double.py"}\n')
    replay_out = tmp_path / 'replay'
    result = tethersim('replay', str(out), '--topics', '/test/estimate', '/test/imu', '/test/uav_state',
                       '--scene', str(listener_only), '--rate', '4', '--out', str(replay_out))
    assert result.returncode == 0, result.stderr

    def decode(bag):
        with AnyReader([bag]) as reader:
            topics = {}
            for connection, _, raw in reader.messages():
                topics.setdefault(connection.topic, []).append(reader.deserialize(raw, connection.msgtype))
            return topics

    original = decode(out / 'bag' / 'bag_0.mcap')
    replayed = decode(replay_out / 'bag' / 'bag_0.mcap')
    for topic in ('/test/estimate', '/test/imu', '/test/uav_state'):
        assert [flatten(m) for m in replayed[topic]] == [flatten(m) for m in original[topic]], topic
    assert [e.point.x for e in replayed['/test/echo']] == [e.point.x for e in original['/test/echo']]
    assert [e.header.stamp for e in replayed['/test/echo']] == [e.header.stamp for e in original['/test/echo']]
    clock = [m.clock.sec + m.clock.nanosec * 1e-9 for m in replayed['/clock']]
    assert clock[-1] == pytest.approx(original['/clock'][-1].clock.sec + original['/clock'][-1].clock.nanosec * 1e-9)


def test_external_node_started_elsewhere_joins_the_run(tmp_path, scene_file):
    """A node marked external is not started but waited for: a scene can span machines."""
    path = scene_file('description: talker runs elsewhere\nduration: 1.0\nrate: 2\nnodes:\n'
                      '  talker:\n    package: not_on_this_machine\n    executable: talker\n    external: true\n'
                      f'  listener:\n    script: {Path(__file__).parent / "nodes" / "listener_double.py"}\n')
    with domain_coordinator.domain_id() as reserved:
        domain = str(reserved)
        env = dict(os.environ, ROS_DOMAIN_ID=domain, ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
        remote = subprocess.Popen([sys.executable, str(Path(__file__).parent / 'nodes' / 'talker_double.py'),
                                   '--ros-args', '-r', '__node:=talker', '-p', 'use_sim_time:=true'],
                                  env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            result = tethersim('run', str(path), '--domain-id', domain, '--out', str(tmp_path / 'out'))
        finally:
            remote.terminate()
            remote.wait(timeout=30)
    assert result.returncode == 0, result.stderr
    assert 'waiting for the recorder and the external node(s) talker' in result.stderr
    bag = read_bag(tmp_path / 'out')
    assert bag.topics['/test/estimate'].count == 50
    assert bag.topics['/test/echo'].count == 50
