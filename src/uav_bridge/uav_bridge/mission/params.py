"""Parameters of the mission node (no rclpy import; the bringup validates scenes with them)."""

from __future__ import annotations

from tether_common.parameters import ParamSpec

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('altitude', 30.0, 'station height above the guide way\'s neutral position (Δz; thesis outdoor 30 m, '
              'indoor 5 m)', 'm', low=1.0, high=500.0, read_only=True),
    ParamSpec('radial', 13.8, 'horizontal distance of the station from the guide way (Δr; default 0.46 x 30 m, the '
              'recommended Δr/Δz; thesis outdoor 15 m, indoor 2.5 m)', 'm', low=0.0, high=500.0, read_only=True),
    ParamSpec('bearing', 0.0, 'direction of the radial offset in world, from x (east) toward y (north)', 'deg',
              low=-360.0, high=360.0, read_only=True),
    ParamSpec('land_time', 0.0, 'sim time at which the mission lands; 0: none (land_before_end, a reel trip)', 's', low=0.0,
              high=1e9, read_only=True),
    ParamSpec('land_before_end', 0.0, 'time reserved for the landing (the return over the pad and the descent): '
              'start it this long before the run ends (the end tethersim run gives its nodes; land_time, if '
              'earlier, still counts); 0: not before land_time', 's', low=0.0, high=1e6,
              read_only=True),
    ParamSpec('pad', [0.0, 0.0], 'landing pad on the boat, horizontal in world (x east, y north): at the end, with '
              'a return_speed, the UAV returns over it to return_height, then lands on it; [0, 0]: over the '
              'guide way', 'm',
              read_only=True),
    ParamSpec('return_speed', 0.0, 'speed of the setpoint returning over the pad, in a straight line (bounded so '
              'that the reel, reeling in, keeps up); 0: no return, the UAV lands where it is', 'm/s', low=0.0,
              high=20.0, read_only=True),
    ParamSpec('return_height', 0.0, 'height in world over the pad where the return ends and the descent onto the pad '
              'starts (a return down the line toward the guide way keeps the tether hanging); 0: the hold altitude',
              'm', low=0.0, high=500.0, read_only=True),
    ParamSpec('return_tolerance', 0.5, 'the landing starts once the UAV is this close to over the pad, '
              'horizontally', 'm', low=0.05, high=10.0, read_only=True),
    ParamSpec('abort_tension', 0.0, 'land when the reel\'s tension estimate exceeds this; 0: only on the reel\'s '
              'fault mode', 'N', low=0.0, high=1e5, read_only=True),
    ParamSpec('abort_after', 0.0, 'land once a reel trip (fault mode, or the abort tension) has lasted this long; '
              '0: on the first tripped reel state', 's', low=0.0, high=60.0, read_only=True),
    ParamSpec('rate', 10.0, 'mission steps and setpoints per second of sim time', 'Hz', low=0.5, high=100.0,
              read_only=True),
    ParamSpec('uav_link', 'command', 'how the UAV is flown: command (the built-in UAV, or SITL on the JSON physics through '
              'mavlink_bridge with command_rate: /uav/command at every step, '
              'its answers in /uav/state; every input a lockstep input, the run reproducible) or services (an '
              'autopilot on its own clock through mavlink_bridge: services /uav/*, /uav/setpoint, inputs as they arrive; the '
              'autopilot runs on its own clock, the run is not reproducible)', choices=('command', 'services'),
              read_only=True),
    ParamSpec('answer_timeout', 1.0, 'uav_link command: a request whose outcome is not in /uav/state this long '
              'after it went out (sim time) stops the mission, as the UAV does not take /uav/command (the built-in '
              'UAV answers at its next state; an autopilot through mavlink_bridge needs its command and arm '
              'timeouts)', 's', low=0.1, high=3600.0, read_only=True),
    ParamSpec('service_timeout', 15.0, 'uav_link services: a set_mode, takeoff or land call not answered this '
              'long after it went out (wall clock and sim time both) ends the mission (phase lost) with the reason '
              'recorded: longer than the bridge\'s command_timeout (5 s), within which it answers every call', 's',
              low=0.1, high=3600.0, read_only=True),
    ParamSpec('arm_service_timeout', 150.0, 'uav_link services: the same for an arm call: longer than the '
              'bridge\'s arm_timeout (120 s), for which it retries a refused arming', 's', low=0.1, high=3600.0,
              read_only=True),
    ParamSpec('link_grace', 10.0, 'a flying mission whose autopilot link is down (closed or stale) this long ends '
              '(phase lost, reason recorded); a reboot of the autopilot in flight ends it at once', 's', low=0.0,
              high=600.0, read_only=True),
    ParamSpec('uav_state_rate', 10.0, 'uav_link command: rate of /uav/state (the built-in UAV\'s state_rate), a '
              'lockstep input without delay', 'Hz', low=0.5, high=1000.0, read_only=True),
    ParamSpec('uav_pose_rate', 100.0, 'uav_link command: rate of /uav/pose (the built-in UAV\'s rate), a lockstep '
              'input without delay', 'Hz', low=0.5, high=1000.0, read_only=True),
    ParamSpec('reel_rate', 50.0, 'uav_link command: rate of /reel/state and /reel/diagnostics (the reel\'s '
              'control_rate), lockstep inputs without delay, each one fed to the trip monitor; 0: no reel in the run',
              'Hz', low=0.0, high=1000.0, read_only=True),
    ParamSpec('retry_period', 2.0, 'wait after a refused request before asking again', 's', low=0.1, high=60.0,
              read_only=True),
    ParamSpec('climb_tolerance', 0.5, 'take-off altitude counted as reached within this', 'm', low=0.05, high=10.0,
              read_only=True),
)
