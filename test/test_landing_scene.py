"""The built-in UAV lands on the pad on the heaving platform, in the graph.

``indoor_flight``, shortened: the UAV starts hovering 2 m over its pad (0.5 m from the guide
way toward the station, 1 m above it, on the platform playing HPR 2), the tether deployed to
it, and the mission lands at 1 s where the UAV is (the return is the mission's, tested with it). The UAV's ground is the pad, carried by
``/platform/reel_pose`` (a lockstep input of the built-in UAV): it must touch down on it,
disarm, and from then on ride with it, every recorded pose on the pad; the reel reels in to
the short hanging tether without a trip and the tether never fouls.
"""

from __future__ import annotations

import numpy as np
import pytest

from tether_bringup.bag_reader import read_bag
from tether_common.lockstep import stamp_ns
from tether_common.rotation import quaternion_rotation
from tether_dynamics.statics.reference_length import reference_length

from tethersim_testing import tethersim
from tethersim_testing import installed_scene
from tethersim_testing import write_scene

DURATION = 12.0
"""s of sim time: the descent of 1-3 m at 0.5 m/s onto the pad heaving about 1 m, and the ride."""
PAD = np.array([0.5, 0.0, 1.0])
"""m: where the UAV rests on its pad, in the reel mount's frame (the scene's)."""


@pytest.fixture(scope='module')
def run(tmp_path_factory):
    base = tmp_path_factory.mktemp('landing')
    scene = installed_scene('indoor_flight')
    assert scene['nodes']['uav']['parameters']['pad'] == PAD.tolist()
    scene['duration'] = DURATION
    scene['reports'] = []
    scene['nodes']['uav']['parameters'].update(start=[0.5, 0.0, 0.0], start_height=3.0)
    scene['nodes']['mission']['parameters'].update(land_before_end=0.0, land_time=1.0, return_speed=0.0)
    length = reference_length(0.5, 2.9).length           # to the attachment 0.1 m below the centre of mass
    for node in ('plant', 'reel'):
        scene['nodes'][node]['parameters']['initial_length'] = length
    scene['nodes']['plant']['parameters']['elements'] = 2    # 1.5 m: stable at the scene's step (0.81 m at 4.9 m)
    path = write_scene(scene, base / 'landing.yaml')
    out = base / 'run'
    result = tethersim('run', path, '--rate', 'max', '--out', str(out), timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    return read_bag(out / 'bag', ['/uav/pose', '/uav/state', '/platform/reel_pose', '/mission/state',
                                  '/reel/diagnostics', '/tether/state'])


def test_the_uav_touches_down_on_the_heaving_pad_and_rides_with_it(run):
    phases = [m.phase for _, m in run.decoded('/mission/state')]
    assert phases[-2:] == ['land', 'landed']
    states = [(stamp_ns(m.header.stamp), m) for _, m in run.decoded('/uav/state')]
    touchdown = next(t for t, m in states if not m.armed)
    assert 1e9 < touchdown < DURATION * 1e9 - 3e9 and not states[-1][1].armed
    reel = {stamp_ns(m.header.stamp): m.pose for _, m in run.decoded('/platform/reel_pose')}
    poses = [(stamp_ns(m.header.stamp), m.pose.position) for _, m in run.decoded('/uav/pose')]
    pad = {}
    for t, pose in reel.items():
        q = pose.orientation
        rotation = quaternion_rotation(np.array([q.x, q.y, q.z, q.w]), 'reel pose').matrix
        pad[t] = np.array([pose.position.x, pose.position.y, pose.position.z]) + rotation @ PAD
    heights = np.array([pad[t][2] for t in sorted(pad)])
    assert heights.max() - heights.min() > 0.2                             # the pad heaves under it
    riding = [(t, p) for t, p in poses if t > touchdown]
    assert len(riding) >= 200
    offset = np.array([riding[0][1].x, riding[0][1].y, riding[0][1].z]) - pad[riding[0][0]]
    assert abs(offset[2]) < 1e-9 and np.hypot(*offset[:2]) < 0.3           # on the pad, near its middle
    for t, p in riding:
        np.testing.assert_allclose([p.x, p.y, p.z], pad[t] + offset, atol=1e-9)
    flying = [(t, p) for t, p in poses if t < touchdown]
    assert all(p.z > pad[t][2] - 1e-9 for t, p in flying)                  # never through it


def test_the_reel_reels_in_to_the_short_tether_without_a_trip_or_fouling(run):
    assert not any(m.safety_trip for _, m in run.decoded('/reel/diagnostics'))
    tether = [m for _, m in run.decoded('/tether/state')]
    assert not any(m.fouling for m in tether)
    assert min(m.clearance_deck for m in tether) > -0.1                    # never more than 0.1 m below the guide way
    assert tether[-1].deployed_length == pytest.approx(reference_length(0.5, 0.9).length, abs=0.15)
