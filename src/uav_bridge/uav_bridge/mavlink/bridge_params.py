"""Parameters of the mavlink_bridge node (no rclpy import; the bringup validates scenes with them).

Link times are wall-clock seconds: the link to an autopilot runs in real time whatever the
graph's clock does; with ``lockstep_input`` set (SITL on the JSON physics) they are seconds of
sim time. Stream rates are in the autopilot's own time (a SITL at ``--speedup`` N sends N times
as many messages per wall second).
"""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('url', 'tcp:127.0.0.1:5760', 'MAVLink link: tcp:HOST:PORT (ArduPilot SITL serves 5760 + 10 x instance), '
              'udp:HOST:PORT / udpin:HOST:PORT (listen), udpout:HOST:PORT (send to)', read_only=True),
    ParamSpec('telemetry_namespace', '/uav', 'namespace of the pose, twist, imu and global topics (the state, '
              'services and setpoint stay under /uav); /autopilot where the JSON physics node publishes the true '
              '/uav/pose', read_only=True),
    ParamSpec('origin', [0.0, 0.0, 0.0], 'position of the autopilot\'s local origin (EKF origin, NED 0) in world, ENU',
              'm', read_only=True),
    ParamSpec('system_id', 255, 'MAVLink system id of the bridge', low=1, high=255, read_only=True),
    ParamSpec('component_id', 191, 'MAVLink component id of the bridge (191: onboard computer)', low=1, high=255,
              read_only=True),
    ParamSpec('heartbeat_period', 1.0, 'period of the bridge\'s own HEARTBEAT (wall clock)', 's', low=0.05, high=10.0,
              read_only=True),
    ParamSpec('link_timeout', 3.0, 'no HEARTBEAT for this long marks the data stale; twice as long reconnects '
              '(wall clock)', 's', low=0.2, high=60.0, read_only=True),
    ParamSpec('reconnect_max', 8.0, 'longest wait between reconnection attempts (exponential back-off from 0.5 s, '
              'wall clock)', 's', low=0.5, high=120.0, read_only=True),
    ParamSpec('stream_timeout', 3.0, 'a requested stream missing for this long is requested again, with back-off '
              '(wall clock)', 's', low=0.2, high=60.0, read_only=True),
    ParamSpec('pose_rate', 50.0, 'requested rate of ATTITUDE and LOCAL_POSITION_NED (/uav/pose, /uav/twist), '
              'autopilot time', 'Hz', low=0.1, high=400.0, read_only=True),
    ParamSpec('imu_rate', 50.0, 'requested rate of HIGHRES_IMU (/uav/imu), autopilot time', 'Hz', low=0.1, high=400.0,
              read_only=True),
    ParamSpec('global_rate', 10.0, 'requested rate of GLOBAL_POSITION_INT (/uav/global), autopilot time', 'Hz',
              low=0.1, high=100.0, read_only=True),
    ParamSpec('ekf_status_rate', 2.0, 'requested rate of EKF_STATUS_REPORT, autopilot time', 'Hz', low=0.1,
              high=50.0, read_only=True),
    ParamSpec('status_period', 1.0, '/uav/state is published on every change and at least this often (wall clock)',
              's', low=0.05, high=60.0, read_only=True),
    ParamSpec('command_timeout', 5.0, 'a mode, takeoff or land command not answered in this time fails (wall clock)',
              's', low=0.5, high=600.0, read_only=True),
    ParamSpec('arm_timeout', 120.0, 'arming is retried with back-off while refused, up to this long (wall clock)',
              's', low=1.0, high=3600.0, read_only=True),
    ParamSpec('lockstep_input', '', 'empty: the link runs in its own thread in wall time; a topic (the JSON '
              'physics\' /uav/pose): the bridge ticks in the graph\'s lockstep after that topic\'s message of the '
              'same tick, reads and writes the link only then and runs its timers on sim time (deterministic '
              'commands to a SITL on the JSON physics)', read_only=True),
    ParamSpec('lockstep_rate', 100.0, 'tick rate with lockstep_input: the rate of that topic\'s producer', 'Hz',
              low=1.0, high=1000.0, read_only=True),
    ParamSpec('command_rate', 0.0, 'with lockstep_input: rate of the mission\'s /uav/command (its rate), a lockstep '
              'input one period late, carried out as the built-in UAV does (a request once per sequence number, '
              'the setpoint while it holds) and answered in /uav/state at every multiple of its period '
              '(state_rate); 0: services and /uav/setpoint only', 'Hz', low=0.0, high=100.0, read_only=True),
    ParamSpec('state_rate', 10.0, 'with command_rate: /uav/state messages per second of sim time, one at every '
              'multiple of its period (the mission\'s uav_state_rate), in place of on every change', 'Hz', low=0.5,
              high=100.0, read_only=True),
    ParamSpec('statustext_lines', 10, 'latest STATUSTEXT lines kept in /uav/state', low=1, high=100, read_only=True),
)
