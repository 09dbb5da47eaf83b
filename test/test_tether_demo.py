"""The tether_demo scene end to end: recorded, every message decoded, the 3-D view Foxglove-ready, the report,
and the same payloads when run again at rate max with every core busy (lockstep determinism).

Every message of a short recording must decode with rosbags (types learnt from the bag) and
with mcap + mcap-ros2-support. Foxglove reads the same ``ros2msg`` schemas with its own
parser (@foxglove/rosmsg, ``parse(text, {ros2: true})``): it splits the text into blocks at
lines starting with ``==``, names each dependency block by its ``MSG: name`` line, and
resolves a field's type to the first block whose name ends with ``/Type`` (or with the
field's full ``pkg/Type``); field names must be lower_snake and constants UPPER_CASE.
:func:`foxglove_schema_errors` applies those rules to every schema of the bag. The markers
must all be in ``world`` (Foxglove registers each marker's frame_id as a coordinate frame
and places markers of the display frame without any transform).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

from tether_dynamics.statics.catenary import THESIS_LINEAR_DENSITY
from tether_models.constants import GRAVITY

from tethersim_testing import bag_contents
from tethersim_testing import busy_cores
from tethersim_testing import installed_scene
from tethersim_testing import processes_of
from tethersim_testing import tethersim
from tethersim_testing import write_scene

DURATION = '4'
PLANT_TOPICS = ('/tether/state', '/tether/nodes', '/tether/markers', '/tether/uav_wrench', '/truth/relative')
FOXGLOVE_BUILTINS = {'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16', 'int32',
                     'uint32', 'int64', 'uint64', 'string', 'wstring', 'time', 'duration', 'builtin_interfaces/Time',
                     'builtin_interfaces/Duration', 'builtin_interfaces/msg/Time', 'builtin_interfaces/msg/Duration'}
_FIELD = re.compile(r'^(?P<type>[a-zA-Z0-9_/]+)(?:<=\d+)?(?:\[\]|\[\d+\]|\[<=\d+\])?\s+(?P<name>[a-zA-Z0-9_]+)'
                    r'(?:\s*=\s*(?P<constant>[^#]*)|\s+[^#\s][^#]*)?\s*(?:#.*)?$')
_MSG = re.compile(r'^MSG: ([^ ]+)\s*(?:#.+)?$')


def foxglove_schema_errors(text: str) -> list[str]:
    """Why Foxglove's ros2msg parser would refuse ``text`` (empty when it would not)."""
    blocks: list[list[str]] = [[]]
    for line in (raw.strip() for raw in text.split('\n')):
        if not line or line.startswith('#'):
            continue
        if line.startswith('=='):
            blocks.append([])
        else:
            blocks[-1].append(line)
    names, fields, errors = [], [], []
    for block in blocks:
        name = ''
        for line in block:
            match = _MSG.match(line)
            if match:
                name = match.group(1)
                continue
            match = _FIELD.match(line)
            if match is None:
                errors.append(f'cannot parse line {line!r}')
                continue
            constant = match.group('constant') is not None
            pattern = r'^[A-Z](?:_?[A-Z0-9]+)*$' if constant else r'^[a-z](?:_?[a-z0-9]+)*$'
            if not re.match(pattern, match.group('name')):
                errors.append(f'invalid {"constant" if constant else "field"} name {match.group("name")!r}')
            if match.group('type') not in FOXGLOVE_BUILTINS and not constant:
                fields.append(match.group('type'))
        names.append(name)
    for type_name in fields:
        end = type_name if '/' in type_name else f'/{type_name}'
        if not any(name.endswith(end) for name in names):
            errors.append(f'no block for field type {type_name!r} (blocks: {names[1:]})')
    return errors


def test_foxglove_rules_refuse_what_foxglove_refuses():
    good = 'geometry_msgs/Point p\n' + '=' * 80 + '\nMSG: geometry_msgs/Point\nfloat64 x\n'
    assert foxglove_schema_errors(good) == []
    assert foxglove_schema_errors(good.replace('MSG: geometry_msgs/Point', 'MSG: geometry_msgs/msg/Point'))
    assert foxglove_schema_errors('float64 Bad_Name\n')
    assert foxglove_schema_errors('uint8 lower=1\n')


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp('tether_demo') / 'run'
    result = tethersim('run', 'tether_demo', '--duration', DURATION, '--rate', '1', '--out', str(out), timeout=300)
    return result, out


def test_tether_demo_runs_and_records_the_plant(run):
    result, out = run
    assert result.returncode == 0, result.stdout + result.stderr
    assert not processes_of(out)
    summary = (out / 'summary.txt').read_text()
    for topic in PLANT_TOPICS:
        assert topic in summary
    for png in ('tether_snapshots.png', 'tether_loads.png', 'tether_clearance.png'):
        assert (out / png).stat().st_size > 10_000
    assert 'tether: UAV-end tension' in summary and 'fouling in' in summary


def _decoded(bag: Path):
    with AnyReader([bag]) as reader:
        by_rosbags = [(c.topic, reader.deserialize(raw, c.msgtype)) for c, _, raw in reader.messages()]
    with open(bag, 'rb') as stream:
        mcap = make_reader(stream, decoder_factories=[DecoderFactory()])
        summary = mcap.get_summary()
        schemas = {channel.topic: summary.schemas[channel.schema_id] for channel in summary.channels.values()}
    with open(bag, 'rb') as stream:
        by_mcap = [(channel.topic, decoded) for _, channel, _, decoded in
                   make_reader(stream, decoder_factories=[DecoderFactory()]).iter_decoded_messages()]
    return by_rosbags, by_mcap, schemas


def test_every_message_decodes_with_both_readers_and_every_schema_with_foxglove_rules(run):
    _, out = run
    by_rosbags, by_mcap, schemas = _decoded(out / 'bag' / 'bag_0.mcap')
    assert [t for t, _ in by_rosbags] == [t for t, _ in by_mcap]
    assert {t for t, _ in by_rosbags} >= set(PLANT_TOPICS)
    assert schemas['/tether/markers'].name == 'visualization_msgs/msg/MarkerArray'
    assert schemas['/tether/markers'].encoding == 'ros2msg'
    for topic, schema in schemas.items():
        assert foxglove_schema_errors(schema.data.decode()) == [], topic
    markers = [m for t, m in by_mcap if t == '/tether/markers']
    assert markers
    for array in markers:
        stamps = {(m.header.stamp.sec, m.header.stamp.nanosec) for m in array.markers}
        assert {m.header.frame_id for m in array.markers} == {'world'} and len(stamps) == 1
        assert {m.ns for m in array.markers} == {'tether', 'reference', 'reel', 'platform', 'uav', 'lowest_point'}


def test_truth_wrench_and_state_agree_step_by_step(run):
    _, out = run
    by_rosbags, _, _ = _decoded(out / 'bag' / 'bag_0.mcap')

    def by_stamp(topic):
        return {(m.header.stamp.sec, m.header.stamp.nanosec): m for t, m in by_rosbags if t == topic}

    states, truths, wrenches = by_stamp('/tether/state'), by_stamp('/truth/relative'), by_stamp('/tether/uav_wrench')
    assert states.keys() == truths.keys() == wrenches.keys()
    difference, weight = [], []
    for stamp, state in states.items():
        uav, reel = state.uav_end, state.reel_end
        relative = truths[stamp].position
        assert [relative.x, relative.y, relative.z] == pytest.approx([uav.x - reel.x, uav.y - reel.y, uav.z - reel.z])
        force = wrenches[stamp].wrench.force
        assert [force.x, force.y, force.z] == [state.force_on_uav.x, state.force_on_uav.y, state.force_on_uav.z]
        assert np.linalg.norm([force.x, force.y, force.z]) == pytest.approx(state.tension_uav, rel=1e-9)
        # The finite-element tether may slacken at the reel (0.2 N there when static).
        assert state.tension_uav > 0.0
        assert state.tension_reel >= 0.0
        difference.append(state.tension_uav - state.tension_reel)
        weight.append(THESIS_LINEAR_DENSITY * GRAVITY * (uav.z - reel.z))
    # A hanging tether: T_B - T_A = mu g dz, on average over the run's dynamics.
    assert np.mean(difference) == pytest.approx(np.mean(weight), rel=0.15)


def test_a_run_at_rate_max_with_every_core_busy_records_the_same_payloads(run, tmp_path):
    """Lockstep: the same scene and seeds give identical messages (every field, bit for bit), topic by topic, in
    order, at the same log times, whether paced at real time or run as fast as possible while other processes load
    every core.
    """
    _, out = run
    loaded = tmp_path / 'loaded'
    with busy_cores():
        result = tethersim('run', 'tether_demo', '--duration', DURATION, '--rate', 'max', '--out', str(loaded),
                           timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    reference, recorded = bag_contents(out), bag_contents(loaded)
    assert set(recorded) == set(reference) and set(reference) >= set(PLANT_TOPICS) | {'/clock', '/platform/imu'}
    for topic, messages in reference.items():
        assert len(messages) >= 4, topic
        assert recorded[topic] == messages, topic



def test_a_process_per_node_records_the_same_payloads_as_the_node_group(run, tmp_path):
    """The scene's nodes in one process (the node group, the default) or each in its own (``compose: false``):
    the same messages, bit for bit, topic by topic and in order; the summaries show the group and its nodes'
    CPU, or one process per node.
    """
    _, out = run
    scene = installed_scene('tether_demo')
    scene['compose'] = False
    separate = tmp_path / 'separate'
    result = tethersim('run', write_scene(scene, tmp_path / 'separate.yaml'), '--duration', DURATION,
                       '--rate', 'max', '--out', str(separate), timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    reference, recorded = bag_contents(out), bag_contents(separate)
    assert set(recorded) == set(reference) and set(reference) >= set(PLANT_TOPICS)
    for topic, messages in reference.items():
        assert recorded[topic] == messages, topic
    rows = {line.split()[0]: line.split() for line in (out / 'summary.txt').read_text().splitlines() if line}
    own = {line.split()[0]: line.split() for line in (separate / 'summary.txt').read_text().splitlines() if line}
    nodes = list(scene['nodes'])
    assert rows['nodes'][1] == '0' and all(len(rows[node]) == 3 for node in nodes)
    assert 'nodes' not in own and all(own[node][1] == '0' for node in nodes)
