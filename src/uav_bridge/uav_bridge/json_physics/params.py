"""Parameters of the json_physics node (no rclpy import; the bringup validates scenes with them).

The vehicle's defaults are :class:`uav_bridge.json_physics.quad_motors.QuadXConfig`'s (a UAV of the
thesis's class, see that module).
"""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('instance', 0, 'SITL instance: its servo packets come to UDP 9002 + 10 x instance', low=0, high=60,
              read_only=True),
    ParamSpec('frame_rate', 800, 'physics frames per second of sim time (SITL follows it; ArduCopter arms only '
              'above 1.8 x its 400 Hz loop; 1/frame_rate must divide 1/rate)', 'Hz', low=100, high=4000,
              read_only=True),
    ParamSpec('rate', 100.0, 'ticks per second of sim time: /uav/pose, /uav/twist, /uav/imu', 'Hz', low=1.0,
              high=1000.0, read_only=True),
    ParamSpec('wrench_rate', 100.0, 'rate of the plant\'s /tether/uav_wrench (its state_rate); the force stamped '
              't acts from t + 1/wrench_rate (the loop\'s explicit delay); 0: no tether', 'Hz', low=0.0,
              high=1000.0, read_only=True),
    ParamSpec('platform_rate', 100.0, 'straight_line: rate of /platform/reel_pose (the platform\'s state_rate)',
              'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('tether_model', 'plant', 'the tether force on the UAV: plant (the plant\'s /tether/uav_wrench) or '
              'straight_line (ArduPilot\'s SIM_Tether model: a straight line from the reel mount on '
              '/platform/reel_pose, the plant\'s deployed length from /tether/state; the plant still runs)',
              choices=('plant', 'straight_line'), read_only=True),
    ParamSpec('line_density', 0.042, 'straight_line: the line\'s mass per length (the thesis\'s tether)', 'kg/m',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('line_spring', 100.0, 'straight_line: spring on the stretch beyond the deployed length (SIM_Tether\'s)',
              'N/m', low=0.0, high=1e6, read_only=True),
    ParamSpec('line_damping', 10.0, 'straight_line: damping of that stretch (SIM_Tether\'s)', 'N s/m', low=0.0,
              high=1e5, read_only=True),
    ParamSpec('mass', 6.0, 'UAV mass', 'kg', low=0.05, high=100.0, read_only=True),
    ParamSpec('inertia', [0.17, 0.17, 0.34], 'principal moments of inertia about the centre of mass, body FLU',
              'kg m^2', read_only=True),
    ParamSpec('arm', 0.45, 'centre to each rotor axis (quad X)', 'm', low=0.01, high=5.0, read_only=True),
    ParamSpec('max_thrust', 36.0, 'thrust of one rotor at full command', 'N', low=0.1, high=1000.0, read_only=True),
    ParamSpec('thrust_expo', 0.65, 'thrust curve T = T_max ((1 - e) u + e u^2) (ArduPilot MOT_THST_EXPO)', '1',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('torque_ratio', 0.016, 'rotor reaction torque per thrust', 'm', low=1e-4, high=1.0, read_only=True),
    ParamSpec('time_constant', 0.04, 'rotor speed lag (first order)', 's', low=1e-3, high=1.0, read_only=True),
    ParamSpec('attach_offset', [0.0, 0.0, -0.1], 'tether attachment from the centre of mass, body FLU (as the '
              'plant\'s uav_attach_offset)', 'm', read_only=True),
    ParamSpec('start', [0.0, 0.0, 0.0], 'centre of mass at rest on the ground before take-off, world (ENU); '
              'SITL\'s home', 'm', read_only=True),
    ParamSpec('heading', 0.0, 'heading at rest, from north towards east (NED yaw)', 'deg', low=-360.0,
              high=360.0, read_only=True),
)
