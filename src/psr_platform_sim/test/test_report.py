"""tracking_report reads /platform/state from an MCAP bag and plots commanded vs. achieved."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer
from rosbags.typesys import Stores
from rosbags.typesys import get_types_from_msg
from rosbags.typesys import get_typestore

from psr_platform_sim.report import tracking_report

MSG = Path(__file__).resolve().parents[2] / 'tether_msgs' / 'msg' / 'PlatformState.msg'
TYPE = 'tether_msgs/msg/PlatformState'


def _write_bag(directory: Path, count: int, roll_error: float) -> Path:
    store = get_typestore(Stores.ROS2_JAZZY)
    store.register(get_types_from_msg(MSG.read_text(), TYPE))
    state = store.types[TYPE]
    header = store.types['std_msgs/msg/Header']
    stamp = store.types['builtin_interfaces/msg/Time']
    with Writer(directory, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        connection = writer.add_connection('/platform/state', TYPE, typestore=store)
        for i in range(count):
            t = 1.0 + 0.01 * i
            roll = 0.2 * np.sin(t)
            msg = state(
                header=header(stamp=stamp(sec=int(t), nanosec=int(round((t % 1) * 1e9))), frame_id='world'),
                slider_height=np.array([1.0, 1.1, 1.2]), slider_velocity=np.zeros(3),
                heave=0.5 * np.sin(t), roll=roll + roll_error, pitch=0.1, yaw=0.0, surge=0.0, sway=0.0,
                heave_rate=0.0, roll_rate=0.0, pitch_rate=0.0, yaw_rate=0.0,
                commanded_heave=0.5 * np.sin(t), commanded_roll=roll, commanded_pitch=0.1,
                in_workspace=i % 4 != 0)
            writer.write(connection, int(t * 1e9), store.serialize_cdr(msg, TYPE))
    return next(directory.glob('*.mcap'))


def test_report_measures_rms_error_and_writes_png(tmp_path):
    bag = _write_bag(tmp_path / 'bag', 200, np.radians(0.5))
    lines = tracking_report(str(bag), str(tmp_path / 'out'))
    assert (tmp_path / 'out' / 'platform_tracking.png').stat().st_size > 10_000
    assert 'roll 0.500 deg' in lines[0]
    assert 'heave 0.0 mm' in lines[0]
    assert 'pitch 0.000 deg' in lines[0]
    assert '200 states' in lines[0]
    assert '25.0 %' in lines[1]
