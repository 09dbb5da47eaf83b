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
    ParamSpec('workdir', '', 'SITL\'s working directory (eeprom, terrain, logs), kept after the run (e.g. under '
              'the run directory); empty: a new temporary directory, removed when the node ends',
              read_only=True),
)


def pace_problem(parameters: dict, rate: float) -> str | None:
    """Why a graph at real-time factor ``rate`` cannot fly this node's SITL, or None.

    SITL on its built-in physics runs at a fixed ``speedup`` times wall time, on its own clock
    outside the lockstep: a graph faster than that outruns the autopilot (at ``--rate max`` a
    90 s scene passed in 19 s wall while SITL lived 76 s of its time, and the mission never got
    past its climb). SITL on the JSON physics (``model: JSON:...``) follows the graph's frames.
    """
    model = str(parameters.get('model', '+'))
    speedup = float(parameters.get('speedup', 1.0))
    if model.upper().startswith('JSON') or rate <= speedup:
        return None
    pace = 'max' if rate == float('inf') else f'{rate:g}'
    return (f'--rate {pace}: SITL runs at a fixed {speedup:g}x wall time (its speedup), outside the lockstep, and '
            f'the graph would outrun the autopilot; run at --rate {speedup:g} or less, or raise the speedup')
