"""Parameters of the sitl node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('binary', '', 'ArduCopter SITL binary; empty: $ARDUPILOT_SITL_BIN (README: building it)',
              read_only=True),
    ParamSpec('defaults', '', 'SITL defaults file; empty: copter.parm beside the binary', read_only=True),
    ParamSpec('instance', 0, 'SITL instance: MAVLink on TCP 5760 + 10 x instance (the bridge\'s url must match)',
              low=0, high=60, read_only=True),
    ParamSpec('speedup', 1.0, 'SITL time per wall time; match the scene\'s rate so both clocks run together', '1',
              low=0.1, high=100.0, read_only=True),
    ParamSpec('model', '+', 'SITL vehicle model (+: built-in quadcopter; JSON:IP for external physics)',
              read_only=True),
    ParamSpec('parameters', [], 'ArduPilot parameters NAME=VALUE overriding the defaults file (e.g. FRAME_TYPE=1 '
              'for the JSON physics\' quad X)', item_type=str, read_only=True),
    ParamSpec('home', '', 'home location lat,lng,alt,yaw; empty: SITL\'s default', read_only=True),
    ParamSpec('workdir', '', 'SITL\'s working directory (eeprom, logs); empty: a new temporary directory',
              read_only=True),
)
