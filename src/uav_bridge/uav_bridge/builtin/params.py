"""Parameters of the builtin_uav node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('mass', 2.0, 'UAV mass', 'kg', low=0.05, high=100.0, read_only=True),
    ParamSpec('inertia', [0.03, 0.03, 0.05], 'principal moments of inertia about the centre of mass, body FLU',
              'kg m^2', read_only=True),
    ParamSpec('attach_offset', [0.0, 0.0, -0.1], 'tether attachment from the centre of mass, body FLU (as the '
              'plant\'s uav_attach_offset)', 'm', read_only=True),
    ParamSpec('start', [0.0, 0.0, 0.0], 'centre of mass at rest on the ground before take-off, world (ENU)', 'm',
              read_only=True),
    ParamSpec('rate', 100.0, 'controller steps and published poses per second of sim time (the body is '
              'integrated at 1 kHz between them)', 'Hz', low=10.0, high=1000.0, read_only=True),
    ParamSpec('land_speed', 0.5, 'descent rate in LAND', 'm/s', low=0.05, high=5.0, read_only=True),
    ParamSpec('start_height', 0.0, 'height above start at which the UAV hovers at t = 0, armed in GUIDED (a '
              'tethered run starts with the tether deployed to the UAV in the air); 0: disarmed, at rest on the '
              'ground at start', 'm', low=0.0, high=500.0, read_only=True),
    ParamSpec('tether_force', 'none', 'the tether\'s force on the UAV: topic (/tether/uav_wrench from the plant, '
              'a lockstep input one wrench_rate period late: the UAV-plant loop\'s delay) or none',
              choices=('none', 'topic'), read_only=True),
    ParamSpec('command_rate', 0.0, 'rate of /uav/command from the mission (its rate): a lockstep input one period '
              'late, each request carried out at the tick that selects it; 0: no mission topic, commands by the '
              'services and /uav/setpoint as they arrive (by hand; not reproducible)', 'Hz', low=0.0, high=100.0,
              read_only=True),
    ParamSpec('imu_rate', 100.0, '/uav/imu messages per second of sim time, one at every multiple of its period '
              '(rate divided by a whole number; the sensors node measures the UAV from the plant\'s truth, not from '
              'this)', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('state_rate', 10.0, '/uav/state messages per second of sim time, one at every multiple of its period '
              '(the mission\'s uav_state_rate)', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('ground', 'level', 'what the UAV lands and rests on: level (the height of start) or pad (a landing '
              'pad on the boat, moving with it: /platform/reel_pose, a lockstep input without delay, carries it)',
              choices=('level', 'pad'), read_only=True),
    ParamSpec('pad', [0.0, 0.0, 0.0], 'ground pad: where the centre of mass rests on the pad, in the frame of '
              '/platform/reel_pose (the reel mount, FLU axes of the boat)', 'm', read_only=True),
    ParamSpec('pad_radius', 1.0, 'ground pad: its extent around pad, horizontally; beyond it the ground is level at '
              'the height of start (a landing elsewhere, as an abort, comes down there)', 'm', low=0.05, high=50.0,
              read_only=True),
    ParamSpec('reel_pose_rate', 100.0, 'ground pad: rate of /platform/reel_pose (the platform\'s state_rate)', 'Hz',
              low=1.0, high=1000.0, read_only=True),
    ParamSpec('wrench_rate', 100.0, 'rate of /tether/uav_wrench: the plant\'s state_rate (lockstep input period)',
              'Hz', low=1.0, high=1000.0, read_only=True),
)
