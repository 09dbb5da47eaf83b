"""Optional effects on the tether, each off unless a scene switches it on.

Aerodynamic drag F_D = 1/2 rho v^2 C_D A (Sec. 9.2.2), split into normal and tangential
parts as in lumped-mass cable codes; a wind field (uniform or power-law shear); internal
Kelvin-Voigt damping (tension += c * strain rate, still tension-only).
"""

from __future__ import annotations

from dataclasses import dataclass

from tether_dynamics.fem.errors import FemError


@dataclass(frozen=True)
class Drag:
    """Quadratic air drag on the tether.

    Attributes:
        diameter: m (projected area per length for normal drag; pi * diameter for tangential).
        cd_normal, cd_tangential: drag coefficients.
        air_density: kg/m^3.
    """

    diameter: float
    cd_normal: float = 1.2
    cd_tangential: float = 0.008
    air_density: float = 1.225

    def __post_init__(self) -> None:
        if self.diameter <= 0 or self.cd_normal < 0 or self.cd_tangential < 0 or self.air_density < 0:
            msg = 'drag needs diameter > 0 and non-negative coefficients and density'
            raise FemError(msg)


@dataclass(frozen=True)
class Wind:
    """Wind velocity w(z) = U * ((z - z_ground) / z_ref)^alpha above z_ground, zero below.

    alpha = 0 gives a uniform field everywhere (z_ground ignored). Only acts with Drag.
    """

    velocity: tuple[float, float, float]
    z_ref: float = 10.0
    alpha: float = 0.0
    z_ground: float = 0.0

    def __post_init__(self) -> None:
        if self.z_ref <= 0 or self.alpha < 0:
            msg = 'wind needs z_ref > 0 and alpha >= 0'
            raise FemError(msg)


@dataclass(frozen=True)
class KelvinVoigt:
    """Internal damping: tension = EA * strain + coefficient * d(strain)/dt, clamped at 0.

    Attributes:
        coefficient: N s (the 'EA-like' damping constant c of a Kelvin-Voigt element).
    """

    coefficient: float

    def __post_init__(self) -> None:
        if self.coefficient < 0:
            msg = 'Kelvin-Voigt coefficient must be non-negative'
            raise FemError(msg)
