"""The tether plant: the tether between a winch on the moving platform and the UAV (thesis Sec. 7.3-7.4, 10.4).

Plain Python (no rclpy); the plant node, the tests and the benchmarks all use this one object::

    from tether_dynamics.plant import PlantConfig, PlantInputs, ReelConfig, TetherPlant, UavConfig

    plant = TetherPlant(PlantConfig(fidelity='quasi_static', elements=20, dt=1e-3,
                                    initial_length=40.0, reel=ReelConfig(input='spool_rate'),
                                    uav=UavConfig(mode='prescribed')))
    out = plant.step(t, PlantInputs(platform_position=..., platform_quaternion=...,
                                    spool_rate=..., uav_position=..., ...))
    out.tension_reel, out.force_on_uav, out.nodes, ...

Contract:
    * :class:`PlantConfig` - fidelity ('quasi_static', 'linear', 'quadratic'), elements, internal
      step dt, effects ('drag', 'wind', 'damping'), the tether (mass per length kg/m, EA N,
      diameter m, drag coefficient), guide_way_offset (3,) m in the boat frame, initial_length m,
      :class:`ReelConfig` (input 'torque' or 'spool_rate', spool radius, inertia, friction,
      drum capacity and end stops) and :class:`UavConfig` (mode 'prescribed' or 'dynamic', mass,
      inertia, attach_offset (3,) from the centre of mass, body frame).
    * :class:`PlantInputs` at time t - platform position, quaternion (x, y, z, w; boat -> world),
      linear and angular velocity (world); reel_torque N m (+ pays out) or spool_rate rad/s
      (+ pays out); UAV position, quaternion, velocity, body rates (prescribed mode; the initial
      state in dynamic mode) or thrust N along body +z and body torque N m (dynamic mode); the
      local sea surface height m (0 when the scene has no waves).
    * :class:`PlantOutputs` - see its docstring: ends, deployed length, payout and spool rate,
      spool angle, tensions and 3-D forces at both ends (and the moment about the UAV's centre
      of mass), departure and arrival angles, lowest point with its clearance above the guide
      way (``clearance_deck``; the reports add the reel's guide_height to give the clearance
      above the deck: :mod:`tether_dynamics.clearance`) and above the sea surface, fouling
      flag (lowest point at or below the sea), kinetic / potential / strain energy, the motor's work, the conserved total
      tether mass, node positions and velocities from reel to UAV, element tensions, arc length
      of the nodes from the guide way, largest strain, and the UAV's state.

    Frames and signs: ENU ``world``; the boat frame is FLU (REP-103); angles above horizontal
    along the tether from the reel towards the UAV (as ``tether_msgs/TetherState``).

    Timing: the first ``step`` sets the initial state; each later ``step(t, ...)`` advances
    from the previous call to t in internal steps of at most ``dt``. Kinematic inputs (platform
    pose, prescribed UAV pose) are samples at t, followed between calls by cubic Hermite
    interpolation of position and velocity; commands (reel torque or spool rate, thrust,
    torque) act from the call that gives them until the next one (one call of delay). A
    spool-rate command is reached linearly over that interval from the spool's current rate,
    so a prescribed spool rate stays continuous (no infinite acceleration at the reel).

    Fidelity: 'quasi_static' solves the elastic catenary of the deployed length every internal
    step (:mod:`.quasi_static`); the winch and a dynamic UAV are integrated against its end
    tensions. 'linear' and 'quadratic' are the finite-element tether with a moving reel
    (:mod:`.fem_reel`: the method for both element orders, the alternatives measured, the
    stable step). What each costs and how close it comes: ``bench/plant_fidelity``.

    Whole runs: a fixed-length case under held inputs (the Chapter 9 pendulum) runs in one call,
    ``TetherPlant.run_held(times, inputs) -> HeldRun``, equal bit for bit to stepping it per sample
    (:mod:`.held_run`).

    Sea surface: ``PlantInputs.sea_surface_height`` is the local wave elevation the scene
    provides (0 without waves); ``clearance_sea`` and ``fouling`` are measured from it.
"""

from tether_dynamics.plant.config import PlantConfig, PlantConfigError, ReelConfig, UavConfig
from tether_dynamics.plant.fem_reel import PlantDivergenceError
from tether_dynamics.plant.io import PlantInputs, PlantOutputs
from tether_dynamics.plant.plant import HeldRun, PlantStepError, TetherPlant

__all__ = ['HeldRun', 'PlantConfig', 'PlantConfigError', 'PlantDivergenceError', 'PlantInputs', 'PlantOutputs',
           'PlantStepError', 'ReelConfig', 'TetherPlant', 'UavConfig']
