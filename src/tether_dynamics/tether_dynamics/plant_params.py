"""Parameters of the plant node (no rclpy import; the bringup validates scenes with them).

Model fidelity, effects, element count, integration step and the publishing rates are
scene parameters, so a run computes and publishes only what its scene asks for.
"""

from __future__ import annotations

from tether_common.parameters import ParamSpec

FIDELITIES = ('quasi_static', 'linear', 'quadratic')
EFFECTS = ('drag', 'wind', 'damping')
REEL_DRIVES = ('spool_rate', 'torque', 'payout_rate')
"""The plant's choices (:mod:`tether_dynamics.plant.config`), repeated so that validating a
scene does not import the compiled plant; a test keeps them equal. ``payout_rate`` drives
the plant's spool-rate input."""
REEL_INPUTS = ('reference', 'command')
UAV_SOURCES = ('fixed', 'topic')

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('fidelity', 'quasi_static', 'tether model: quasi_static (catenary of the deployed length each '
              'step), linear or quadratic finite elements (Ch. 8)', choices=FIDELITIES, read_only=True),
    ParamSpec('elements', 20, 'number of finite elements (ignored by quasi_static)', low=1, high=400,
              read_only=True),
    ParamSpec('effects', [], 'effects on the finite-element tether: drag, wind (needs drag), damping '
              '(Kelvin-Voigt); none when empty', choices=EFFECTS, item_type=str, read_only=True),
    ParamSpec('drag_coefficient', 1.2, 'normal drag coefficient of the tether (effect drag)', low=0.0, high=10.0,
              read_only=True),
    ParamSpec('wind', [0.0, 0.0, 0.0], 'uniform wind velocity in world (effect wind)', 'm/s', read_only=True),
    ParamSpec('damping', 0.0, 'Kelvin-Voigt coefficient c, tension += c d(strain)/dt (effect damping)', 'N s',
              low=0.0, high=1e6, read_only=True),
    ParamSpec('integration_step', 0.0005, 'internal step of the plant: the finite-element step, or how often '
              'the quasi-static catenary is solved between plant steps', 's',
              low=1e-6, high=0.1, read_only=True),
    ParamSpec('state_rate', 100.0, 'plant output steps per second: /tether/state, /tether/uav_wrench, '
              '/truth/relative each step', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('nodes_rate', 10.0, 'rate of /tether/nodes (a divisor of state_rate)', 'Hz', low=0.1, high=1000.0,
              read_only=True),
    ParamSpec('markers_rate', 10.0, 'rate of /tether/markers (a divisor of state_rate)', 'Hz', low=0.1,
              high=1000.0, read_only=True),
    ParamSpec('linear_density', 0.042, 'tether linear density (Sec. 3.2.1)', 'kg/m', low=1e-4, high=10.0,
              read_only=True),
    ParamSpec('axial_stiffness', 2.0e4, 'tether axial stiffness EA', 'N', low=1.0, high=1e9, read_only=True),
    ParamSpec('diameter', 0.0045, 'tether diameter (drag), 4.5 mm coax of Sec. 4.1', 'm', low=1e-4, high=0.1,
              read_only=True),
    ParamSpec('initial_length', 0.0, 'deployed length at start; 0: the catenary reference length of the '
              'initial relative position', 'm', low=0.0, high=1000.0, read_only=True),
    ParamSpec('guide_way_offset', [0.0, 0.0, 0.0], 'guide-way position from the reel mount '
              '(/platform/reel_pose) in the FLU boat frame', 'm', read_only=True),
    ParamSpec('reel_input', 'reference', 'what drives the spool: reference (a scripted reel: the deployed '
              'length follows the catenary reference length of the true relative position, Eq. 4.4/4.5) or '
              'command (/reel/command, from the smart reel)', choices=REEL_INPUTS, read_only=True),
    ParamSpec('reel_drive', 'spool_rate', 'what /reel/command sets (reel_input command): spool_rate, torque '
              '(the plant integrates the winch, Eq. 7.26) or payout_rate (the sender integrates its own drive; '
              'the spool turns at payout_rate / spool_radius); a command of another kind is refused',
              choices=REEL_DRIVES, read_only=True),
    ParamSpec('spool_radius', 0.05, 'spool radius d: payout rate = d x spool rate', 'm', low=1e-3, high=2.0,
              read_only=True),
    ParamSpec('spool_inertia', 0.01, 'inertia of the empty drum and motor (Eq. 7.26)', 'kg m^2', low=1e-6,
              high=100.0, read_only=True),
    ParamSpec('spool_friction', 0.0, 'viscous friction of the spool', 'N m s/rad', low=0.0, high=100.0,
              read_only=True),
    ParamSpec('reel_capacity', 100.0, 'tether on the drum plus deployed (100 m on the thesis reel, Sec. 4.1)',
              'm', low=1.0, high=10000.0, read_only=True),
    ParamSpec('reference_gain', 5.0, 'scripted reel: payout rate per metre of length error, added to the '
              "reference length's rate of change", '1/s', low=0.0, high=1000.0, read_only=True),
    ParamSpec('uav_source', 'fixed', 'UAV attachment point: fixed (uav_position, a rigidly mounted surrogate '
              'as in Sec. 5.1) or topic (/uav/pose, an external UAV)', choices=UAV_SOURCES, read_only=True),
    ParamSpec('uav_position', [3.22, 0.0, 5.9], 'fixed UAV attachment point in world', 'm', read_only=True),
    ParamSpec('uav_attach_offset', [0.0, 0.0, -0.1], 'tether attachment from the UAV centre of mass in its FLU '
              'body frame (uav_source topic)', 'm', read_only=True),
    ParamSpec('platform_rate', 100.0, 'rate of /platform/reel_pose and /platform/reel_twist: the platform\'s '
              'state_rate (lockstep input period; used with no delay)', 'Hz', low=1.0, high=1000.0, read_only=True),
    ParamSpec('uav_rate', 100.0, 'rate of /uav/pose and /uav/twist (uav_source topic; lockstep input period, '
              'used with no delay: the UAV side takes /tether/uav_wrench one step late)', 'Hz', low=1.0,
              high=1000.0, read_only=True),
    ParamSpec('reel_command_rate', 100.0, 'rate of /reel/command (reel_input command); the plant uses the '
              'command one reel period old: the reel loop\'s one-step delay', 'Hz', low=1.0, high=1000.0,
              read_only=True),
    ParamSpec('sea_level', -1.5, 'world height of the calm sea surface the clearance and fouling flag are '
              'measured from (waves under the tether are not modelled)', 'm', low=-1000.0, high=1000.0,
              read_only=True),
)
