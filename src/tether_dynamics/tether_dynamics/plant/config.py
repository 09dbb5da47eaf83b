"""Configuration of the tether plant: tether, reel, UAV, fidelity and effects (thesis Sec. 7.3-7.4)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tether_dynamics.statics.catenary import THESIS_LINEAR_DENSITY
from tether_models.constants import GRAVITY

FIDELITIES = ('quasi_static', 'linear', 'quadratic')
EFFECTS = ('drag', 'wind', 'damping')
REEL_INPUTS = ('torque', 'spool_rate')
UAV_MODES = ('prescribed', 'dynamic')
RESHAPE_METHODS = ('ale', 'last_element', 'uniform', 'insert')


class PlantConfigError(ValueError):
    """A plant configuration that cannot be run; the message names the field."""


def _positive(name: str, value: float) -> None:
    if not (np.isfinite(value) and value > 0.0):
        msg = f'{name} must be a positive number, got {value!r}'
        raise PlantConfigError(msg)


def _vector(name: str, value: object, shape: tuple[int, ...] = (3,)) -> np.ndarray:
    arr = np.asarray(value, float)
    if arr.shape != shape or not np.all(np.isfinite(arr)):
        msg = f'{name} must be a finite array of shape {shape}, got {value!r}'
        raise PlantConfigError(msg)
    return arr


@dataclass(frozen=True)
class ReelConfig:
    """The winch (Eq. 7.26 / 7.42): a drum of radius d and inertia J holding the undeployed tether.

    Attributes:
        input: 'torque' (motor torque in, N m, + pays out; the spool's rate follows from
            Eq. 7.26) or 'spool_rate' (rad/s, + pays out, prescribed kinematically).
        spool_radius: d, m; payout rate = d * spool rate.
        inertia: J_d of the empty drum and motor, kg m^2 (the wound tether adds mu s_d d^2).
        viscous_friction: N m s/rad, opposing the spool rate.
        total_length: tether on drum + deployed, m (the drum's capacity); the wound mass
            mu (total_length - deployed) is the drum's share of the conserved total.
        min_length, max_length: end stops of the deployed length, m: the spool stops there
            (rate set to zero) and the stop is reported in the outputs.
    """

    input: str = 'spool_rate'
    spool_radius: float = 0.05
    inertia: float = 0.01
    viscous_friction: float = 0.0
    total_length: float = 150.0
    min_length: float = 0.5
    max_length: float = 120.0

    def __post_init__(self) -> None:
        if self.input not in REEL_INPUTS:
            msg = f'reel.input must be one of {REEL_INPUTS}, got {self.input!r}'
            raise PlantConfigError(msg)
        for name in ('spool_radius', 'inertia', 'total_length', 'min_length', 'max_length'):
            _positive(f'reel.{name}', getattr(self, name))
        if self.viscous_friction < 0.0:
            msg = f'reel.viscous_friction must be >= 0, got {self.viscous_friction!r}'
            raise PlantConfigError(msg)
        if not self.min_length < self.max_length <= self.total_length:
            msg = ('reel lengths must satisfy min_length < max_length <= total_length, got '
                   f'{self.min_length}, {self.max_length}, {self.total_length}')
            raise PlantConfigError(msg)


@dataclass(frozen=True)
class UavConfig:
    """The UAV end (Eq. 7.44-7.45).

    Attributes:
        mode: 'prescribed' (pose and velocity are inputs) or 'dynamic' (a rigid body driven by
            thrust along its body z axis (FLU, up) and a body torque, gravity and the tether).
        mass: kg.  inertia : (3, 3) about the centre of mass, body frame, kg m^2.
        attach_offset: (3,) centre of mass to the tether attachment point, body (FLU) frame, m.
    """

    mode: str = 'prescribed'
    mass: float = 2.0
    inertia: tuple = ((0.03, 0.0, 0.0), (0.0, 0.03, 0.0), (0.0, 0.0, 0.05))
    attach_offset: tuple[float, float, float] = (0.0, 0.0, -0.1)

    def __post_init__(self) -> None:
        if self.mode not in UAV_MODES:
            msg = f'uav.mode must be one of {UAV_MODES}, got {self.mode!r}'
            raise PlantConfigError(msg)
        _positive('uav.mass', self.mass)
        inertia = _vector('uav.inertia', self.inertia, (3, 3))
        if not np.allclose(inertia, inertia.T) or np.any(np.linalg.eigvalsh(inertia) <= 0.0):
            msg = 'uav.inertia must be symmetric positive definite'
            raise PlantConfigError(msg)
        _vector('uav.attach_offset', self.attach_offset)


@dataclass(frozen=True)
class PlantConfig:
    """Everything a :class:`~tether_dynamics.plant.TetherPlant` needs; see the package docstring.

    Attributes:
        fidelity: 'quasi_static' (elastic catenary solved each step), 'linear' or
            'quadratic' (finite elements with a moving reel; quadratic elements only with
            reshape 'ale').
        elements: number of finite elements at the initial deployed length (and the number of
            output points - 1 for the quasi-static fidelity).
        element_length: nominal element rest length h, m; default initial_length / elements.
            Elements are split and merged at the reel so the count follows the deployed length.
        dt: internal step, s (the FEM's explicit step; the quasi-static reel integration step).
        effects: any of 'drag', 'wind', 'damping' (FEM only; the quasi-static model is static).
        mass_per_length: mu, kg/m.  ea : axial stiffness EA, N.  diameter : m.
        drag_coefficient: normal drag coefficient (tangential: 0.008).  air_density : kg/m^3.
        damping: Kelvin-Voigt coefficient c (tension += c d(strain)/dt), N s.
        wind: (3,) uniform wind velocity, world frame, m/s.
        gravity: m/s^2.
        guide_way_offset: (3,) guide-way position in the boat frame (FLU, from the platform origin), m.
        initial_length: deployed (unstretched) length at the first step, m.
        reshape: how the FEM mesh follows the deployed length: 'ale' (this package's method);
            'last_element', 'uniform', 'insert' are the peers' methods, kept for the benchmark.
        reel, uav: :class:`ReelConfig`, :class:`UavConfig`.
    """

    fidelity: str = 'quasi_static'
    elements: int = 20
    element_length: float | None = None
    dt: float = 1e-3
    effects: tuple[str, ...] = ()
    mass_per_length: float = THESIS_LINEAR_DENSITY
    ea: float = 2.0e4
    diameter: float = 0.004
    drag_coefficient: float = 1.2
    air_density: float = 1.225
    damping: float = 0.0
    wind: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gravity: float = GRAVITY
    guide_way_offset: tuple[float, float, float] = (0.0, 0.0, 0.5)
    initial_length: float = 10.0
    reshape: str = 'ale'
    reel: ReelConfig = field(default_factory=ReelConfig)
    uav: UavConfig = field(default_factory=UavConfig)

    def __post_init__(self) -> None:
        if self.fidelity not in FIDELITIES:
            msg = f'fidelity must be one of {FIDELITIES}, got {self.fidelity!r}'
            raise PlantConfigError(msg)
        unknown = [e for e in self.effects if e not in EFFECTS]
        if unknown:
            msg = f'effects must be among {EFFECTS}, got {unknown}'
            raise PlantConfigError(msg)
        if 'wind' in self.effects and 'drag' not in self.effects:
            msg = "effect 'wind' acts through drag: add 'drag' to effects"
            raise PlantConfigError(msg)
        if self.reshape not in RESHAPE_METHODS:
            msg = f'reshape must be one of {RESHAPE_METHODS}, got {self.reshape!r}'
            raise PlantConfigError(msg)
        if not (isinstance(self.elements, (int, np.integer)) and self.elements >= 1):
            msg = f'elements must be an integer >= 1, got {self.elements!r}'
            raise PlantConfigError(msg)
        for name in ('dt', 'mass_per_length', 'ea', 'diameter', 'gravity', 'initial_length', 'air_density'):
            _positive(name, getattr(self, name))
        if self.element_length is not None:
            _positive('element_length', self.element_length)
        if self.damping < 0.0 or self.drag_coefficient < 0.0:
            msg = 'damping and drag_coefficient must be >= 0'
            raise PlantConfigError(msg)
        _vector('wind', self.wind)
        _vector('guide_way_offset', self.guide_way_offset)
        if not self.reel.min_length <= self.initial_length <= self.reel.max_length:
            msg = (f'initial_length {self.initial_length} m must lie within the reel stops '
                   f'[{self.reel.min_length}, {self.reel.max_length}] m')
            raise PlantConfigError(msg)

    @property
    def nominal_element_length(self) -> float:
        """h, m: the rest length of every element but the one at the reel."""
        return self.element_length if self.element_length is not None else self.initial_length / self.elements
