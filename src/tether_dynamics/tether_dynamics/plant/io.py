"""Inputs and outputs of one plant step (all vectors in the ENU ``world`` frame unless named)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def _zeros() -> np.ndarray:
    return np.zeros(3)


def _identity_quaternion() -> np.ndarray:
    return np.array([0.0, 0.0, 0.0, 1.0])


@dataclass
class PlantInputs:
    """What drives the plant at time t.

    Kinematic samples (platform pose and velocity, a prescribed UAV's pose and velocity, the
    sea surface height) are values AT t; between two calls the plant follows them by cubic
    Hermite interpolation of positions with their velocities. Commands (reel torque or spool
    rate, UAV thrust and torque) are held from the call that gives them: the ones given at
    t act from t until the next call (one step of explicit delay, deterministic).

    Attributes:
        platform_position: (3,) boat-frame origin in world, m.
        platform_quaternion: (4,) x, y, z, w; rotates boat-frame vectors into world.
        platform_velocity: (3,) m/s, world.  platform_angular_velocity : (3,) rad/s, world.
        reel_torque: N m, + pays out (reel input 'torque').
        spool_rate: rad/s, + pays out (reel input 'spool_rate').
        uav_position: (3,) centre of mass, m.  uav_quaternion : (4,) x, y, z, w, body (FLU) -> world.
        uav_velocity: (3,) m/s.  uav_angular_velocity : (3,) rad/s, body frame.
            (UAV mode 'prescribed'; in mode 'dynamic' they are the initial state at the first call.)
        uav_thrust: N along body +z.  uav_torque : (3,) N m, body frame (UAV mode 'dynamic').
        sea_surface_height: m, the local sea surface elevation under the tether (0 if the
            scene has no waves); the clearance above the sea is measured from it.
    """

    platform_position: np.ndarray = field(default_factory=_zeros)
    platform_quaternion: np.ndarray = field(default_factory=_identity_quaternion)
    platform_velocity: np.ndarray = field(default_factory=_zeros)
    platform_angular_velocity: np.ndarray = field(default_factory=_zeros)
    reel_torque: float = 0.0
    spool_rate: float = 0.0
    uav_position: np.ndarray = field(default_factory=lambda: np.array([10.0, 0.0, 10.0]))
    uav_quaternion: np.ndarray = field(default_factory=_identity_quaternion)
    uav_velocity: np.ndarray = field(default_factory=_zeros)
    uav_angular_velocity: np.ndarray = field(default_factory=_zeros)
    uav_thrust: float = 0.0
    uav_torque: np.ndarray = field(default_factory=_zeros)
    sea_surface_height: float = 0.0


@dataclass
class PlantOutputs:
    """The plant's state after a step: everything ``tether_msgs/TetherState`` and ``TetherNodes`` carry.

    Attributes:
        t: s.  fidelity : 'quasi_static', 'linear' or 'quadratic'.  element_count : elements now.
        reel_end, uav_end: (3,) tether ends (guide way, UAV attachment point), m.
        reel_end_velocity, uav_end_velocity: (3,) their velocities, m/s.
        deployed_length: unstretched deployed length, m.  payout_rate : m/s, + out.
        spool_angle: rad.  spool_rate : rad/s, + pays out.  reel_torque : N m, the motor torque
            applied (input 'torque') or the one the prescribed rate required (input 'spool_rate').
        at_stop: the deployed length sits on a reel end stop.
        tension_reel, tension_uav: N, tether tension at the guide way and at the UAV.
        force_on_reel: (3,) force of the tether on the guide way, N.
        force_on_uav, moment_on_uav: (3,) force (N) and moment about the UAV's centre of mass
            (N m), world frame, that the tether applies to the UAV.
        departure_angle, arrival_angle: rad, the tether's tangent above horizontal at the reel
            and at the UAV, pointing from the reel towards the UAV.
        lowest_point: (3,) m.  clearance_deck : lowest point above the guide way's height
            (the deck), m.  clearance_sea : lowest point above the sea surface, m.
        fouling: True when the lowest point is at or below the sea surface.
        kinetic_energy, potential_energy (gravitational, zero at z = 0), strain_energy : J, of the
            deployed tether.  reel_work : J, work done by the motor on the spool since the start.
        total_tether_mass: drum + deployed, kg (conserved).
        nodes, velocities: (n, 3) from the reel to the UAV, m and m/s.
        tensions: (n - 1,) per element, N.  arc_length : (n,) unstretched distance of each node
            from the guide way, m.  max_strain : largest element strain.
        uav_position, uav_velocity, uav_acceleration: (3,) centre of mass, world.
        uav_quaternion: (4,) x, y, z, w.  uav_angular_velocity : (3,) body frame, rad/s.
    """

    t: float
    fidelity: str
    element_count: int
    reel_end: np.ndarray
    uav_end: np.ndarray
    reel_end_velocity: np.ndarray
    uav_end_velocity: np.ndarray
    deployed_length: float
    payout_rate: float
    spool_angle: float
    spool_rate: float
    reel_torque: float
    at_stop: bool
    tension_reel: float
    tension_uav: float
    force_on_reel: np.ndarray
    force_on_uav: np.ndarray
    moment_on_uav: np.ndarray
    departure_angle: float
    arrival_angle: float
    lowest_point: np.ndarray
    clearance_deck: float
    clearance_sea: float
    fouling: bool
    kinetic_energy: float
    potential_energy: float
    strain_energy: float
    reel_work: float
    total_tether_mass: float
    nodes: np.ndarray
    velocities: np.ndarray
    tensions: np.ndarray
    arc_length: np.ndarray
    max_strain: float
    uav_position: np.ndarray
    uav_velocity: np.ndarray
    uav_acceleration: np.ndarray
    uav_quaternion: np.ndarray
    uav_angular_velocity: np.ndarray
