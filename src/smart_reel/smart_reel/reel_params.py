"""Parameters of the reel node (no rclpy import; the bringup validates scenes with them).

Sources: "thesis" values are stated in the thesis (section given); "class" values are
nominal values of the motor's class (NEMA 23 integrated brushless servo with drive, 48 V,
the Moog Animatics SM23165 family of Table 5.1), not measurements of the prototype;
"chosen" values are this model's choices where the thesis is silent, with the reason.
"""

from __future__ import annotations

from tether_common.parameters import ParamSpec
from tether_dynamics.clearance import GUIDE_HEIGHT

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('controller', 'catenary', 'length controller: catenary (Sec. 4.2), taut (constant torque, '
              'Sec. 5.1) or locked (spool braked, no control)', choices=('catenary', 'taut', 'locked'),
              read_only=True),
    ParamSpec('relative_source', 'truth', 'relative position input: truth (/truth/relative, like the '
              "thesis's MoCap) or estimate (/estimate/relative from the estimator)",
              choices=('truth', 'estimate'), read_only=True),
    ParamSpec('reference_mode', 'poly', 'reference-length model: poly (Eq. 4.4/4.5 with blend) or exact '
              '(heave-robust length solved, Sec. 3.1.2)', choices=('poly', 'exact'), read_only=True),
    ParamSpec('min_slack', 0.0, 'the reference length is at least the chord plus this: slack for the error of the '
              'relative position where the model\'s own slack is smaller (short ranges: the landing on the pad); '
              '0: the model alone (smart_reel.controller)', 'm', low=0.0, high=10.0, read_only=True),
    ParamSpec('lead', 0.0, 'the relative height the controller uses is the input extrapolated this far ahead '
              'with its vertical rate (dz + lead dz_rate): with the input\'s age, input_delay, it makes up for the '
              'loop latency; 0: the input as it is (the thesis)', 's', low=0.0, high=1.0, read_only=True),
    ParamSpec('step', 0.01, 'winch step and /reel/command period; the plant step it exchanges with', 's',
              low=1e-4, high=0.1, read_only=True),
    ParamSpec('control_rate', 50.0, 'PD controller rate (Sec. 4.2)', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('radial_rate', 4.0, 'rate at which the relative radial distance reaches the controller '
              '(Sec. 4.2, serial dGPS link of Sec. 5.5)', 'Hz', low=0.1, high=1000.0, read_only=True),
    ParamSpec('input_delay', 0.01, 'age of the inputs used at a tick: the latest /tether/state and relative '
              'position stamped at or before t - input_delay (one plant step: the loop delay)', 's',
              low=0.0, high=1.0, read_only=True),
    ParamSpec('tether_state_rate', 100.0, 'rate of /tether/state: the plant\'s state_rate (lockstep input '
              'period)', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('relative_rate', 100.0, 'rate of the relative-position input: the plant\'s state_rate for '
              '/truth/relative, the estimator\'s rate for /estimate/relative (lockstep input period)', 'Hz',
              low=1.0, high=1000.0, read_only=True),
    ParamSpec('sync_gain', 10.0, 'rate at which the commanded payout pulls the plant\'s deployed length onto '
              'the reel\'s (smart_reel.reel)', '1/s', low=0.0, high=1000.0, read_only=True),
    ParamSpec('wait_for_inputs', False, 'run tick t only once /tether/state and the relative position have '
              'reached t - input_delay (false: run on /clock with whatever has arrived; the plant, which does '
              'not wait for /reel/command, then finds the command of every tick)', read_only=True),
    ParamSpec('kp', 2707.0, 'proportional gain on the length error (`tethersim reel tune`: 60 s JONSWAP, 36 runs)', 'V/m',
              low=0.0, high=1e5, read_only=True),
    ParamSpec('kd', 9.72, 'derivative gain on the length error (`tethersim reel tune`: 60 s JONSWAP, 36 runs)', 'V s/m',
              low=0.0, high=1e4, read_only=True),
    ParamSpec('ki', 0.0, 'integral gain; 0 is the thesis PD (conditional-integration anti-windup)', 'V/(m s)',
              low=0.0, high=1e5, read_only=True),
    ParamSpec('voltage_limit', 48.0, 'controller output limit (class: the drive supply)', 'V',
              low=0.1, high=400.0, read_only=True),
    ParamSpec('alpha_slow', 0.2, 'Eq. 4.1 filter coefficient at low relative velocity (thesis Sec. 4.2)', '1',
              low=0.001, high=1.0, read_only=True),
    ParamSpec('schedule_upper', 0.3, 'scheduler threshold the filter turns on at (thesis Sec. 4.2)', 'm/s',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('schedule_lower', 0.1, 'lowered threshold once the speed fell below it (thesis Sec. 4.2)', 'm/s',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('taut_torque', 2.43, 'taut controller reel-in spool torque, above the static friction (Sec. 6.1.4 '
              "states the tension, not the torque: 2.43 N m holds the thesis's taut mean, 27.52 N, at rest at the "
              '0.088 m drum radius of the surrogate scenes; 7x the static friction)', 'N m', low=0.01, high=100.0,
              read_only=True),
    ParamSpec('initial_length', 0.0, 'deployed length at start; 0 takes it from the first /tether/state', 'm',
              low=0.0, high=1000.0, read_only=True),
    ParamSpec('motor_resistance', 1.5, 'winding resistance (class)', 'ohm', low=0.01, high=100.0, read_only=True),
    ParamSpec('motor_inductance', 2.5e-3, 'winding inductance (class)', 'H', low=1e-6, high=1.0, read_only=True),
    ParamSpec('motor_torque_constant', 0.10, 'torque constant = back-EMF constant (class)', 'N m/A',
              low=1e-4, high=10.0, read_only=True),
    ParamSpec('motor_rotor_inertia', 1.2e-5, 'rotor inertia (class)', 'kg m^2', low=1e-8, high=1.0,
              read_only=True),
    ParamSpec('motor_current_limit', 12.0, 'drive peak current limit (class)', 'A', low=0.01, high=200.0,
              read_only=True),
    ParamSpec('supply_voltage', 48.0, 'drive supply (class: 20-48 V DC)', 'V', low=1.0, high=400.0,
              read_only=True),
    ParamSpec('gear_ratio', 40.0, 'gearbox ratio (chosen: 48 V no-load spool speed 115 rpm, above the '
              '100 rpm of Sec. 4.1)', '1', low=1.0, high=1000.0, read_only=True),
    ParamSpec('encoder_counts', 8000, 'motor encoder counts per motor revolution (class)', 'counts/rev',
              low=1, high=10**7, read_only=True),
    ParamSpec('friction_viscous', 0.02, 'drivetrain viscous friction at the spool shaft (chosen)', 'N m s/rad',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('friction_coulomb', 0.25, 'drivetrain Coulomb friction at the spool shaft (chosen)', 'N m',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('friction_static', 0.35, 'drivetrain static friction (stiction) at the spool shaft (chosen)',
              'N m', low=0.0, high=100.0, read_only=True),
    ParamSpec('drum_inertia', 0.004, 'empty drum inertia with flanges and slip ring (chosen)', 'kg m^2',
              low=0.0, high=100.0, read_only=True),
    ParamSpec('core_radius', 0.05, 'drum radius under the first layer (thesis Sec. 4.1: 50 mm minimum bend '
              'radius)', 'm', low=0.005, high=2.0, read_only=True),
    ParamSpec('drum_width', 0.12, 'drum width between the flanges (chosen)', 'm', low=0.005, high=2.0,
              read_only=True),
    ParamSpec('tether_diameter', 0.0045, 'tether diameter (thesis Sec. 4.1)', 'm', low=1e-4, high=0.1,
              read_only=True),
    ParamSpec('tether_capacity', 100.0, 'tether length on the full spool (thesis Sec. 4.1)', 'm',
              low=1.0, high=10000.0, read_only=True),
    ParamSpec('linear_density', 0.042, 'tether mass per length (thesis Sec. 3.2.1)', 'kg/m', low=1e-4,
              high=10.0, read_only=True),
    ParamSpec('axial_stiffness', 2.0e4, "tether axial stiffness EA, as the plant's (the drive's model of the "
              'pull between plant steps, smart_reel.tension_model)', 'N', low=1.0, high=1e9, read_only=True),
    ParamSpec('arm_deadband', 20.0, 'guide-arm follower dead-band on reversal (thesis Sec. 6.1.3)', 'deg',
              low=0.0, high=90.0, read_only=True),
    ParamSpec('arm_encoder_bits', 12, 'guide-arm absolute encoder resolution (MAE-3, Table 5.1)', 'bit',
              low=1, high=24, read_only=True),
    ParamSpec('min_clearance', 0.1, 'safety: stop paying out when the lowest point is closer than this to the '
              'deck or the water', 'm', low=0.0, high=100.0, read_only=True),
    ParamSpec('min_departure_angle', -20.0, 'safety: stop paying out when the guide-arm reading is below this '
              '(at least half the dead-band below the lowest nominal departure angle)',
              'deg', low=-90.0, high=90.0, read_only=True),
    ParamSpec('max_tension', 80.0, 'safety: stop reeling in when the tension estimate exceeds this', 'N',
              low=0.1, high=10000.0, read_only=True),
    ParamSpec('trip_delay', 0.1, 'safety: a condition trips once it has lasted this long, or at once past its hard '
              'band (the lowest point on the deck or the water, a reading half the arm\'s dead band below its '
              'limit, a tension 20 N over it); 0: every tick past a limit trips (smart_reel.safety)', 's',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('guide_height', GUIDE_HEIGHT, 'guide way above the deck: the deck clearance is /tether/state '
              'clearance_deck (below the guide way) plus this', 'm', low=0.0, high=10.0, read_only=True),
)
