"""AutopilotState: which autopilot, link up/stale/resumed, reboots, readiness, reasons."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault('MAVLINK20', '1')

from pymavlink.dialects.v20 import ardupilotmega as mavlink  # noqa: E402

from uav_bridge.mavlink.autopilot_state import AutopilotState  # noqa: E402

ARMED = 128
CUSTOM = 1


def _message(system, build):
    """Encode with source ``system`` and decode again, as a received message."""
    encoder = mavlink.MAVLink(None, system, 1)
    parser = mavlink.MAVLink(None, 0, 0)
    return parser.parse_buffer(build(encoder).pack(encoder))[0]


def _heartbeat(custom_mode=0, armed=False, system=1, kind=2, autopilot=3):
    return _message(system, lambda m: m.heartbeat_encode(kind, autopilot, CUSTOM | (ARMED if armed else 0),
                                                         custom_mode, 3))


def _attitude(boot_ms, system=1):
    return _message(system, lambda m: m.attitude_encode(boot_ms, 0, 0, 0, 0, 0, 0))


def _local(boot_ms):
    return _message(1, lambda m: m.local_position_ned_encode(boot_ms, 0, 0, 0, 0, 0, 0))


def _text(text, severity=6):
    return _message(1, lambda m: m.statustext_encode(severity, text.encode()))


def _connected_state():
    state = AutopilotState(link_timeout=3.0)
    state.connection_made()
    return state


def test_locks_on_the_first_vehicle_and_ignores_ground_stations_and_itself():
    state = _connected_state()
    assert state.on_message(_heartbeat(system=255, kind=6, autopilot=8), 0.0) == []   # our own id
    assert state.on_message(_heartbeat(system=42, kind=6, autopilot=8), 0.0) == []    # another GCS
    assert state.system_id is None
    assert state.on_message(_heartbeat(custom_mode=4, system=1), 0.1) == ['link_up']
    assert state.system_id == 1 and state.mode == 'GUIDED' and not state.armed
    state.on_message(_heartbeat(custom_mode=9, armed=True, system=7), 0.2)   # a second vehicle
    assert state.mode == 'GUIDED' and not state.armed


def test_stale_after_the_link_timeout_and_resumed_after_a_gap():
    state = _connected_state()
    assert state.stale(0.0)
    state.on_message(_heartbeat(), 1.0)
    assert not state.stale(3.9)
    assert state.stale(4.1)
    assert state.heartbeat_age(4.1) == pytest.approx(3.1)
    assert state.on_message(_heartbeat(), 5.0) == ['resumed']
    assert state.on_message(_heartbeat(), 6.0) == []
    state.connection_lost()
    assert state.stale(6.1)
    state.connection_made()
    assert state.on_message(_heartbeat(), 7.0) == ['link_up']
    assert state.reconnects == 2


def test_reboot_when_boot_time_goes_backwards_beyond_the_tolerance():
    state = _connected_state()
    state.on_message(_heartbeat(), 0.0)
    state.on_message(_attitude(50_000), 0.1)
    assert state.on_message(_local(49_500), 0.1) == []          # an EKF message lagging by 0.5 s: jitter
    assert state.on_message(_attitude(300), 0.2) == ['reboot']
    assert state.reboots == 1
    assert not state.position_ready(0.2)
    assert state.on_message(_attitude(320), 0.3) == []


def test_position_ready_only_with_local_position_and_waiting_reasons():
    state = AutopilotState(link_timeout=3.0)
    assert state.waiting_for(0.0, 'tcp:h:1', []) == 'connection to tcp:h:1'
    state.connection_made()
    assert state.waiting_for(0.0, 'tcp:h:1', []) == 'first HEARTBEAT on tcp:h:1'
    state.on_message(_heartbeat(), 0.0)
    assert not state.position_ready(0.5)
    assert 'no LOCAL_POSITION_NED' in state.waiting_for(0.5, 'tcp:h:1', [])
    state.on_message(_local(600), 0.6)
    assert state.position_ready(0.7)
    assert state.waiting_for(0.7, 'tcp:h:1', ['HIGHRES_IMU']) == 'telemetry streams: HIGHRES_IMU'
    assert state.waiting_for(0.7, 'tcp:h:1', []) == ''
    assert not state.position_ready(3.7)        # LOCAL_POSITION_NED stopped
    assert state.waiting_for(5.0, 'tcp:h:1', []).startswith('HEARTBEAT (none for 5.0 s)')


def test_statustext_lines_and_warnings_since():
    state = AutopilotState(statustext_lines=3)
    state.connection_made()
    state.on_message(_heartbeat(), 0.0)
    mark = state.status_serial
    for text, severity in [('EKF3 IMU0 initialised', 6), ('PreArm: Need Position Estimate', 2),
                           ('PreArm: Gyros inconsistent', 2), ('EKF3 IMU0 is using GPS', 6)]:
        state.on_message(_text(text, severity), 0.1)
    assert state.status_text == ['PreArm: Need Position Estimate', 'PreArm: Gyros inconsistent',
                                 'EKF3 IMU0 is using GPS']
    assert state.warnings_since(mark) == ['PreArm: Need Position Estimate', 'PreArm: Gyros inconsistent']
    assert state.warnings_since(state.status_serial) == []


def test_mode_names_of_the_vehicle_type():
    state = _connected_state()
    assert state.mode_number('GUIDED') is None      # vehicle type not known yet
    state.on_message(_heartbeat(custom_mode=0), 0.0)
    assert state.mode == 'STABILIZE'
    assert state.mode_number('guided') == 4 and state.mode_number('LAND') == 9
    assert state.mode_number('NOSUCHMODE') is None
    assert 'GUIDED' in state.mode_names()
