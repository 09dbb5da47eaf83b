"""Scenes: the thesis's Chapter 9 pendulum (Sec. 9.1.1) and a sea-state-4 boat end motion."""

from __future__ import annotations

import numpy as np

from tether_dynamics.fem.effects import Drag, KelvinVoigt, Wind
from tether_dynamics.fem.end_bodies import Pinned, PointMass, PrescribedMotion, RigidBody
from tether_dynamics.fem.model import Scene, Tether
from tether_dynamics.fem.statics import hanging_shape
from tether_dynamics.plant.config import PlantConfig, ReelConfig, UavConfig
from tether_models.constants import GRAVITY

# Sec. 9.1.1: string, pivot, release point, rigid body.
PENDULUM_LENGTH = 5.875
PENDULUM_MU = 0.03
PENDULUM_EA = 1000.0
PENDULUM_PIVOT = (0.0, 0.0, 0.0)
PENDULUM_RELEASE = (-0.1456, -5.7318, -1.1417)
PENDULUM_MASS = 0.432
PENDULUM_RHO_C = (0.0, 0.0, 0.03752)
# The thesis prints this tensor in "kg/m^2"; its size only fits kg mm^2 (a 0.43 kg body a
# few cm across), so it is converted to kg m^2. It is used as the inertia about the
# attachment point, which is what Eq. 7.6 needs.
PENDULUM_INERTIA = 1e-6 * np.array([[1161.58, -3.31, 9.51], [-3.31, 1171.85, 93.23], [9.51, 93.23, 369.85]])
# e_b3 co-linear with e_2 (Sec. 9.1.1). We take e_b3 = -e_2, i.e. along the string away
# from the pivot, so the centre of mass hangs beyond the attachment point; e_b1 = e_1.
PENDULUM_ROTATION = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
THESIS_DT = 1e-4
THESIS_SPAN = 10.0
THESIS_WALL = {'linear': 32.6, 'quadratic': 71.2}


def pendulum(element: str = 'linear', n_elem: int = 5, body: str = 'rigid', *,
             drag: Drag | None = None, wind: Wind | None = None,
             damping: KelvinVoigt | None = None, tension_only: bool = True) -> Scene:
    """The Chapter 9 pendulum released from rest in its static hanging shape.

    body: 'rigid' (Eq. 7.13 with the thesis's rho_c and inertia) or 'point'.
    """
    tet = Tether(PENDULUM_LENGTH, PENDULUM_MU, PENDULUM_EA, n_elem, element, tension_only)
    nodes = hanging_shape(tet, np.array(PENDULUM_PIVOT), np.array(PENDULUM_RELEASE))
    far = (RigidBody(PENDULUM_MASS, PENDULUM_RHO_C, PENDULUM_INERTIA, PENDULUM_ROTATION) if body == 'rigid'
           else PointMass(PENDULUM_MASS))
    return Scene(tet, Pinned(PENDULUM_PIVOT), far, nodes, drag=drag, wind=wind, damping=damping)


def pendulum_plant(element: str = 'linear', n_elem: int = 5, dt: float = THESIS_DT) -> PlantConfig:
    """The pendulum as the tether plant runs it (:mod:`tether_dynamics.plant`): the pivot at the
    guide way, the reel held (spool-rate input; a rate of 0 keeps the length), the end a 'dynamic'
    UAV body of the point mass's mass with its attachment at its centre; ``element`` 'linear' or
    'quadratic'. Release it with ``PlantInputs(uav_position=PENDULUM_RELEASE)``.
    """
    return PlantConfig(fidelity=element, elements=n_elem, dt=dt, initial_length=PENDULUM_LENGTH,
                       guide_way_offset=PENDULUM_PIVOT, mass_per_length=PENDULUM_MU, ea=PENDULUM_EA,
                       gravity=GRAVITY, reel=ReelConfig(input='spool_rate', min_length=0.5,
                                                        max_length=2.0 * PENDULUM_LENGTH),
                       uav=UavConfig(mode='dynamic', mass=PENDULUM_MASS, attach_offset=(0.0, 0.0, 0.0)))


def boat_motion(exit_point: tuple[float, float, float] = (0.0, 0.0, 1.0), heave: float = 1.1,
                heave_period: float = 5.0, roll_deg: float = 21.8, roll_period: float = 5.0) -> PrescribedMotion:
    """Tether exit point of a boat heaving and rolling harmonically (sea state 4, Sec. 2.7.2).

    The roll axis is the world x axis through the origin; the exit point sits at
    ``exit_point`` in the boat frame. Defaults: 2.2 m heave range and +-21.8 deg roll (the
    largest of the thesis's HPR profiles) at the short end (5 s) of sea-state-4 periods.
    """
    p = np.asarray(exit_point, float)
    wh, wr = 2 * np.pi / heave_period, 2 * np.pi / roll_period
    amp = np.radians(roll_deg)

    def parts(t: np.ndarray) -> tuple:
        t = np.asarray(t, float)
        phi, dphi, ddphi = amp * np.sin(wr * t), amp * wr * np.cos(wr * t), -amp * wr**2 * np.sin(wr * t)
        c, s = np.cos(phi), np.sin(phi)
        y = c * p[1] - s * p[2]
        z = s * p[1] + c * p[2]
        return t, phi, dphi, ddphi, y, z

    def position(t: np.ndarray) -> np.ndarray:
        t, _, _, _, y, z = parts(t)
        return np.stack([np.full_like(t, p[0]), y, z + heave * np.sin(wh * t)], axis=-1)

    def velocity(t: np.ndarray) -> np.ndarray:
        t, _, dphi, _, y, z = parts(t)
        return np.stack([np.zeros_like(t), -dphi * z, dphi * y + heave * wh * np.cos(wh * t)], axis=-1)

    def acceleration(t: np.ndarray) -> np.ndarray:
        t, _, dphi, ddphi, y, z = parts(t)
        return np.stack([np.zeros_like(t), -ddphi * z - dphi**2 * y,
                         ddphi * y - dphi**2 * z - heave * wh**2 * np.sin(wh * t)], axis=-1)

    return PrescribedMotion(position, velocity, acceleration)
