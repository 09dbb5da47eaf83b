"""The plant node's plain-Python parts: parameters, the scripted reel, the scene markers."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from builtin_interfaces.msg import Time
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from visualization_msgs.msg import Marker
from visualization_msgs.msg import MarkerArray

from tether_bringup.scene import find_scene
from tether_bringup.scene import load_scene
from tether_dynamics.plant import config
from tether_dynamics.plant_markers import reference_shape
from tether_dynamics.plant_markers import SceneMarkers
from tether_dynamics.plant_params import EFFECTS
from tether_dynamics.plant_params import FIDELITIES
from tether_dynamics.plant_params import PARAMETERS
from tether_dynamics.plant_params import REEL_DRIVES
from tether_dynamics.scripted_reel import ScriptedReel
from tether_dynamics.statics.reference_length import reference_length

GUIDE = np.array([0.0, 0.0, -1.1])
UAV = np.array([3.22, 0.0, 5.9])


def test_parameter_choices_are_the_plants():
    assert FIDELITIES == config.FIDELITIES
    assert EFFECTS == config.EFFECTS
    assert set(REEL_DRIVES) == {*config.REEL_INPUTS, 'payout_rate'}
    assert {spec.name for spec in PARAMETERS} >= {'fidelity', 'elements', 'effects', 'integration_step',
                                                   'state_rate', 'nodes_rate', 'markers_rate'}


def test_tether_demo_scene_is_the_sec_5_1_geometry():
    scene = load_scene(find_scene('tether_demo'))
    plant = next(node for node in scene.nodes if node.name == 'plant').parameters
    dr, dz = math.hypot(*plant['uav_position'][:2]), plant['uav_position'][2] - (-1.1)
    assert dz == pytest.approx(7.0)
    assert dr / dz == pytest.approx(0.46)


def test_scripted_reel_pays_out_the_reference_rate_and_closes_the_length_error():
    reel = ScriptedReel(gain=5.0)
    length, dt = 7.0, 0.01
    for k in range(300):
        t = k * dt
        dz = 7.0 - 0.5 * t  # the platform heaves up at 0.5 m/s
        length += reel.step(t, (3.22, 0.0, dz), length) * dt
    reference_now = reference_length(3.22, 7.0 - 0.5 * 2.99).length
    rate = (reference_now - reference_length(3.22, 7.0 - 0.5 * 2.98).length) / dt
    assert reel.reference == reference_now
    # the error left is the rate's one-step lag, far below the initial 1 m error
    assert abs(length - reference_now) < 2.0 * abs(rate) * dt
    assert ScriptedReel(gain=2.0).step(0.0, (3.22, 0.0, 7.0), 7.0) == pytest.approx(
        2.0 * (reference_length(3.22, 7.0).length - 7.0))
    with pytest.raises(ValueError, match='gain must be >= 0'):
        ScriptedReel(gain=-1.0)


def test_reference_shape_is_the_catenary_of_the_reference_length_between_the_ends():
    points = reference_shape(GUIDE, UAV, 4001)
    np.testing.assert_allclose(points[0], GUIDE, atol=1e-12)
    np.testing.assert_allclose(points[-1], UAV, atol=1e-9)
    arc = np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1))
    assert arc == pytest.approx(reference_length(3.22, 7.0).length, rel=1e-6)
    assert np.all(points[:, 1] == 0.0)
    assert points[1, 2] > points[0, 2]  # never longer than the slack length: it leaves the reel upwards (Sec. 4.3)


def test_markers_are_all_in_world_with_the_step_stamp_and_survive_serialization():
    stamp = Time(sec=12, nanosec=340_000_000)
    nodes = reference_shape(GUIDE, UAV, 21)
    markers = SceneMarkers()
    first = deserialize_message(serialize_message(markers.fill(Time(sec=1), reference_shape(GUIDE, UAV, 31), GUIDE,
                                                               np.array([0.0, 0.0, 0.0, 1.0]), GUIDE, UAV,
                                                               nodes[5], False)), MarkerArray)
    array = markers.fill(stamp, nodes, GUIDE, np.array([0.0, 0.0, 0.0, 1.0]), GUIDE, UAV, nodes[5], True)
    decoded = deserialize_message(serialize_message(array), MarkerArray)
    assert len(first.markers[0].points) == 31 and first.markers[-1].color.g > 0.8   # refilled: 31 points, then 21
    assert [m.ns for m in decoded.markers] == ['tether', 'reference', 'reel', 'platform', 'uav', 'lowest_point']
    for marker in decoded.markers:
        assert marker.header.frame_id == 'world'
        assert (marker.header.stamp.sec, marker.header.stamp.nanosec) == (12, 340_000_000)
        assert marker.action == Marker.ADD and marker.lifetime.sec == 0 and marker.lifetime.nanosec == 0
        q = marker.pose.orientation
        assert q.x**2 + q.y**2 + q.z**2 + q.w**2 == pytest.approx(1.0)
        if marker.type == Marker.LINE_STRIP:
            assert len(marker.points) >= 2 and marker.scale.x > 0
        else:
            assert min(marker.scale.x, marker.scale.y, marker.scale.z) > 0
    tether = decoded.markers[0]
    assert len(tether.points) == 21 and tether.points[-1].z == pytest.approx(UAV[2])
    np.testing.assert_array_equal([[p.x, p.y, p.z] for p in tether.points], nodes)
    assert [m.scale.x for m in decoded.markers] == [m.scale.x for m in first.markers]
    assert decoded.markers[-1].color.r > 0.8 and decoded.markers[-1].color.g < 0.2  # fouling: red


@pytest.mark.parametrize('args, message', [
    (['-p', 'initial_length:=500.0'], 'initial_length 500.0 m must lie within the reel stops'),
    (['-p', 'nodes_rate:=30.0'], 'nodes_rate = 30 Hz must divide state_rate = 100 Hz'),
    (['-p', 'fidelity:=cubic'], 'parameter fidelity: expected a string from {quasi_static, linear, quadratic}'),
])
def test_node_refuses_a_bad_configuration_in_one_line(args, message):
    result = subprocess.run([sys.executable, '-m', 'tether_dynamics.plant_node', '--ros-args', *args],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert message in result.stderr and 'Traceback' not in result.stderr
