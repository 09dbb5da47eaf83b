"""`outdoor_flight_ardupilot` twice at once, on two real ArduCopter SITLs capped at different paces: the same messages.

The mission flies ArduCopter over ``/uav/command`` (the bridge's ``command_rate``), every
input of every node is selected by stamp, and SITL reads the bridge's bytes at fixed frames
(``lockstep_input``, ``lockstep_window: 0``), so the two runs, sharing the two cores and
each SITL capped at its own ``--speedup``, must record the same payloads on every topic:
the wait for ArduCopter's EKF, GUIDED, the arming, the take-off and the first seconds of the
climb toward the station, with the plant's tether on the UAV and the reel paying out.
"""

from __future__ import annotations

import os
import threading

import pytest
import yaml

from sitl_process import SitlProcess
from sitl_process import sitl_binary
from sitl_process import put_on_instance
from sitl_process import sitl_unavailable
from tether_bringup.bag_reader import read_bag
from tether_bringup.scene import find_scene
from tether_common.lockstep import stamp_ns
from tethersim_testing import bag_payloads
from tethersim_testing import differing_topics
from tethersim_testing import processes_of
from tethersim_testing import tethersim

UNAVAILABLE = sitl_unavailable()
pytestmark = [pytest.mark.skipif(UNAVAILABLE is not None, reason=UNAVAILABLE or ''), pytest.mark.long_run]

DURATION = 47.0
"""s of sim time: ArduCopter's EKF uses GPS at about 41 s; GUIDED, arming and take-off follow within 1.5 s."""
SPEEDUPS = {'sitl at 100x': 100.0, 'sitl at 2x': 2.0}
"""SITL's caps on its pace (the graph, at --rate max, sets it below them or not, as the load allows)."""
INSTANCE_TOPICS = ('/uav/state',)
"""Topics whose text names the link (the instance's TCP port) while connecting: compared without that text."""


def _scene(directory, instance: int, speedup: float) -> str:
    directory.mkdir()
    scene = yaml.safe_load(find_scene('outdoor_flight_ardupilot').read_text())
    scene['duration'] = DURATION
    scene['reports'] = []
    put_on_instance(scene, instance, directory / 'sitl')
    scene['nodes']['sitl']['parameters']['speedup'] = speedup
    path = directory / 'scene.yaml'
    path.write_text(yaml.safe_dump(scene))
    return str(path)


@pytest.fixture(scope='module')
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp('ardupilot')
    claims = {name: SitlProcess(base / f'claim-{k}') for k, name in enumerate(SPEEDUPS)}
    results = {}
    try:
        scenes = {name: _scene(base / str(k), claims[name].config.instance, SPEEDUPS[name])
                  for k, name in enumerate(SPEEDUPS)}

        def run(name: str) -> None:
            results[name] = tethersim('run', scenes[name], '--rate', 'max', '--out', str(base / name), timeout=1200,
                                      env=dict(os.environ, ARDUPILOT_SITL_BIN=str(sitl_binary())))
        threads = [threading.Thread(target=run, args=(name,)) for name in SPEEDUPS]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    finally:
        for claim in claims.values():
            claim.close()
    for name, result in results.items():
        assert result.returncode == 0, f'{name}: {result.stderr[-3000:]}'
    assert processes_of(base) == []
    return {name: base / name for name in SPEEDUPS}


def _without_link_text(text: str) -> str:
    """A /uav/state's text with the link's waiting text left out (it names the instance's port)."""
    head, rest = text.split('waiting_for=', 1)
    return head + rest.split(', heartbeat_age=', 1)[1]


def test_both_runs_record_the_same_payloads_on_every_topic(runs):
    first, second = runs.values()
    assert set(bag_payloads(first)) >= {'/uav/command', '/uav/state', '/uav/pose', '/autopilot/pose',
                                        '/uav/rotor_thrust', '/mission/state', '/tether/state', '/reel/state'}
    assert differing_topics(first, second, {topic: _without_link_text for topic in INSTANCE_TOPICS}) == []


def test_the_commands_are_answered_in_uav_state_and_arducopter_took_off(runs):
    bag = read_bag(runs['sitl at 100x'] / 'bag')
    commands = [m for _, m in bag.decoded('/uav/command')]
    sent = {}
    for m in commands:
        if m.sequence:
            sent.setdefault(m.sequence, (stamp_ns(m.header.stamp), m.request))
    assert [request for _, request in sent.values()][:3] == ['set_mode', 'arm', 'takeoff']
    states = [(stamp_ns(m.header.stamp), m) for _, m in bag.decoded('/uav/state')]
    for sequence, (stamp, request) in list(sent.items())[:3]:
        answered_at, answered = next((t, m) for t, m in states if m.command_sequence == sequence)
        assert answered_at > stamp and answered.command_success, (request, answered.command_message)
    phases = [m.phase for _, m in bag.decoded('/mission/state')]
    assert phases == ['wait', 'guided', 'arm', 'takeoff', 'climb']
    assert states[-1][1].armed and states[-1][1].mode == 'GUIDED'
    heights = [m.pose.position.z for _, m in bag.decoded('/uav/pose')]
    assert heights[-1] > heights[0] + 0.5                # climbing from the pad
