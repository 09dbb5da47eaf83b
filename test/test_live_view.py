"""The live view end to end: ``tethersim run --live`` served to a real protocol client, not the project's code.

The client (``test/live_client/client.mjs``, installed by ``make live-client``) is Foxglove's
own: the ``@foxglove/ws-protocol`` client over ``ws`` under Node.js, decoding each message
with the ros2msg parser and CDR reader the Foxglove app uses (``@foxglove/rosmsg``,
``@foxglove/rosmsg2-serialization``). It connects while the run starts, subscribes to
``/tether/markers`` and ``/tether/state`` once advertised (the run's clock starts only then:
``--live-wait``), and prints what it received as JSON lines. What it decoded must be what the same run's bag holds at the same log time, and
the run's payloads must be those of the same scene run without ``--live``; the replay of
that bag serves the same messages again.
"""

from __future__ import annotations

import json
import math
import shutil
import socket
import subprocess
import time
from pathlib import Path

import pytest
import yaml
from rclpy.serialization import deserialize_message

from tether_bringup.bag_reader import read_bag
from tether_common.message_types import message_class

from tethersim_testing import ROOT
from tethersim_testing import differing_topics
from tethersim_testing import start_tethersim
from tethersim_testing import tethersim
from tethersim_testing import write_scene

CLIENT = ROOT / 'test' / 'live_client' / 'client.mjs'
SUBSCRIBED = ('/tether/markers', '/tether/state')
RUN_TIMEOUT = 300.0
"""Seconds a run (and its client) may take on a loaded machine before the test gives up on it."""
SCENE = {
    'description': 'live view test: platform, quasi-static tether plant with markers, smart reel',
    'duration': 3.0, 'rate': 'max', 'clock_step': 0.05,
    'nodes': {
        'platform': {'package': 'psr_platform_sim', 'executable': 'platform',
                     'parameters': {'profile': 'hpr1', 'seed': 1, 'profile_duration': 60.0}},
        'plant': {'package': 'tether_dynamics', 'executable': 'plant',
                  'parameters': {'fidelity': 'quasi_static', 'integration_step': 0.01, 'state_rate': 100.0,
                                 'nodes_rate': 10.0, 'markers_rate': 10.0, 'reel_input': 'reference',
                                 'uav_source': 'fixed', 'uav_position': [3.22, 0.0, 5.9]}},
        'reel': {'package': 'smart_reel', 'executable': 'reel', 'parameters': {'relative_source': 'truth'}},
    },
}

needs_client = pytest.mark.skipif(shutil.which('node') is None or not (CLIENT.parent / 'node_modules').is_dir(),
                                reason='the live view test client needs Node.js and `make live-client`')


def _wait_for_url(run: subprocess.Popen, stats: Path) -> str:
    """The live server's URL once the recorder has started it (None if the run ended first)."""
    deadline = time.monotonic() + RUN_TIMEOUT
    while run.poll() is None and time.monotonic() < deadline:
        if stats.exists():
            text = yaml.safe_load(stats.read_text())
            if isinstance(text, dict) and 'url' in text:
                return text['url']
        time.sleep(0.05)
    raise AssertionError(f'the run served nothing: {run.communicate()[1][-2000:]}')


def _serve_and_watch(args: list[str], run_dir: Path) -> list[dict]:
    """Run ``tethersim ARGS --out run_dir --live 0 --live-wait`` with the client connected (the clock starts once it
    has subscribed); return the client's events.
    """
    run = start_tethersim(*args, '--out', str(run_dir), '--live', '0', '--live-wait')
    client = None
    try:
        url = _wait_for_url(run, run_dir / 'live.yaml')
        client = subprocess.Popen(['node', str(CLIENT), url, *SUBSCRIBED], stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)
        _, run_errors = run.communicate(timeout=RUN_TIMEOUT)
        assert run.returncode == 0, run_errors[-2000:]
        output, client_errors = client.communicate(timeout=RUN_TIMEOUT)
    finally:
        run.kill()
        if client is not None:
            client.kill()
    assert client.returncode == 0, client_errors[-2000:]
    return [json.loads(line) for line in output.splitlines()]


@pytest.fixture(scope='module')
def runs(tmp_path_factory):
    """The scene run with --live and a client connected, and run again without; the first run's bag replayed live."""
    base = tmp_path_factory.mktemp('live')
    scene = write_scene(SCENE, base / 'scene.yaml')
    live = _serve_and_watch(['run', scene], base / 'live')
    plain = tethersim('run', scene, '--out', str(base / 'plain'), timeout=RUN_TIMEOUT)
    assert plain.returncode == 0, plain.stderr[-2000:]
    replayed = _serve_and_watch(['replay', str(base / 'live'), '--topics', *SUBSCRIBED, '--rate', '4'],
                                base / 'replay')
    return base, live, replayed


def _received(events: list[dict]) -> dict[str, list[dict]]:
    found: dict[str, list[dict]] = {topic: [] for topic in SUBSCRIBED}
    for event in events:
        if event['event'] == 'message':
            found[event['topic']].append(event)
    return found


def _same(decoded, expected, where: str) -> list[str]:
    """Where the client's decoded value differs from the rclpy-decoded one (Foxglove's field names are the .msg ones)."""
    if hasattr(expected, 'get_fields_and_field_types'):
        return [difference for name in expected.get_fields_and_field_types()
                for difference in _same(decoded[name], getattr(expected, name), f'{where}.{name}')]
    if isinstance(expected, (list, tuple)) or hasattr(expected, 'tolist'):
        items = list(expected)
        if len(decoded) != len(items):
            return [f'{where}: {len(decoded)} items, the bag {len(items)}']
        return [difference for index, (a, b) in enumerate(zip(decoded, items))
                for difference in _same(a, b, f'{where}[{index}]')]
    if isinstance(expected, float):
        same = decoded == expected or (math.isnan(decoded) and math.isnan(expected))
        return [] if same else [f'{where}: {decoded!r}, the bag {expected!r}']
    if isinstance(expected, int) and isinstance(decoded, str):
        decoded = int(decoded)  # a 64-bit integer, a BigInt in JavaScript, printed as a string
    return [] if decoded == expected else [f'{where}: {decoded!r}, the bag {expected!r}']


def _mismatches(run_dir: Path, events: list[dict]) -> list[str]:
    """Each received message that is not, field for field, the bag's message of its topic at its log time."""
    bag = read_bag(run_dir / 'bag')
    by_time = {(m.topic, m.log_time): m.data for m in bag.messages}
    problems = []
    for topic, received in _received(events).items():
        kind = message_class(bag.topics[topic].type_name)
        for event in received:
            data = by_time.get((topic, int(event['logTime'])))
            if data is None:
                problems.append(f'{topic}: no message at {event["logTime"]} ns in the bag')
                continue
            problems += _same(event['message'], deserialize_message(data, kind), f'{topic}@{event["logTime"]}')
    return problems


@needs_client
def test_client_sees_every_recorded_topic_with_the_bags_schema(runs):
    base, live, _ = runs
    bag = read_bag(base / 'live' / 'bag')
    advertised = {channel['topic']: channel for event in live if event['event'] == 'advertise'
                  for channel in event['channels']}
    assert set(advertised) == set(bag.topics)
    first = next(event for event in live if event['event'] == 'advertise')
    assert {channel['topic'] for channel in first['channels']} == set(bag.topics), \
        'the URL was announced before every channel was advertised'
    for topic, channel in advertised.items():
        assert (channel['encoding'], channel['schemaEncoding']) == ('cdr', 'ros2msg'), topic
        assert channel['schemaName'] == bag.topics[topic].type_name, topic
        assert channel['schema'] == bag.topics[topic].definition, topic


@needs_client
def test_client_decodes_the_bags_messages(runs):
    base, live, _ = runs
    received = _received(live)
    assert all(received[topic] for topic in SUBSCRIBED), {topic: len(found) for topic, found in received.items()}
    assert _mismatches(base / 'live', live) == []
    for topic, found in received.items():
        times = [int(event['logTime']) for event in found]
        assert times == sorted(set(times)), f'{topic}: out of order or repeated'
    markers = received['/tether/markers'][-1]['message']['markers']
    assert {marker['ns'] for marker in markers} >= {'tether', 'reel', 'uav'}
    assert {marker['header']['frame_id'] for marker in markers} == {'world'}


@needs_client
def test_what_the_3d_panel_shows_is_in_world(runs):
    base, _, _ = runs
    bag = read_bag(base / 'live' / 'bag')
    shown = {name for name, topic in bag.topics.items()
             if topic.type_name in ('geometry_msgs/msg/PoseStamped', 'visualization_msgs/msg/MarkerArray')}
    assert {'/tether/markers', '/platform/reel_pose'} <= shown
    frames = set()
    for message in bag.messages:
        if message.topic in shown:
            decoded = deserialize_message(message.data, message_class(bag.topics[message.topic].type_name))
            frames |= {m.header.frame_id for m in decoded.markers} if hasattr(decoded, 'markers') \
                else {decoded.header.frame_id}
    assert frames == {'world'}


@needs_client
def test_server_time_is_the_runs_sim_time(runs):
    base, live, _ = runs
    [info] = [event for event in live if event['event'] == 'serverInfo']
    assert 'time' in info['capabilities']
    times = [int(event['time']) for event in live if event['event'] == 'time']
    assert len(times) == 1
    clock = [m.log_time for m in read_bag(base / 'live' / 'bag').messages if m.topic == '/clock']
    assert times[0] in clock


@needs_client
def test_payloads_identical_with_and_without_live(runs):
    base, _, _ = runs
    assert differing_topics(base / 'live', base / 'plain') == []


@needs_client
def test_summary_reports_the_servers_share(runs):
    base, _, _ = runs
    stats = yaml.safe_load((base / 'live' / 'live.yaml').read_text())
    assert stats['offered'] == sum(topic.count for topic in read_bag(base / 'live' / 'bag').topics.values())
    assert stats['served'] + stats['dropped'] == stats['offered']
    line = next(line for line in (base / 'live' / 'summary.txt').read_text().splitlines()
                if line.startswith('live view:'))
    assert f'{stats["served"]} of {stats["offered"]} messages' in line


@needs_client
def test_replay_serves_the_bag_again(runs):
    base, _, replayed = runs
    received = _received(replayed)
    assert all(received[topic] for topic in SUBSCRIBED), {topic: len(found) for topic, found in received.items()}
    first = next(event for event in replayed if event['event'] == 'advertise')
    assert {channel['topic'] for channel in first['channels']} == {*SUBSCRIBED, '/clock'}
    assert _mismatches(base / 'live', replayed) == []


def test_a_port_in_use_is_a_usage_error(tmp_path):
    with socket.create_server(('127.0.0.1', 0)) as held:
        port = held.getsockname()[1]
        result = tethersim('run', write_scene(SCENE, tmp_path / 'scene.yaml'), '--out', str(tmp_path / 'run'),
                           '--live', str(port))
    assert result.returncode == 2
    assert result.stderr.splitlines() == [f'tethersim: error: --live: cannot listen on 127.0.0.1:{port} '
                                          '(Address already in use); give another port (--live PORT)']
    assert not (tmp_path / 'run').exists()


def test_a_bad_port_is_a_usage_error(tmp_path):
    result = tethersim('run', '--live', 'tether_demo')
    assert result.returncode == 2
    assert 'expected a TCP port' in result.stderr and 'Traceback' not in result.stderr
