"""The tether's pull on the drum between two plant steps: ``T(L) ≈ T_p - k (L - L_p)``.

The reel integrates its drive against the tension the plant reported at its last step
(``T_p`` at deployed length ``L_p``, one loop delay old). A hanging tether pulls almost the
same whatever the reel does within a step, but a taut one is a stiff spring: with
``k = EA/L`` (2500 N/m for 8 m of EA = 20 kN) on a drum radius of 0.088 m against the spool's
inertia, the spring's period is a few tenths of a second, and a spring force one or two
10 ms steps old feeds it energy (negative damping of about ``δ ω_n / 2``): the taut
controller's run bounced between slack and 200 N. So the drive takes the tension at its
own length, the plant's value moved along the local slope ``k = -∂T_A/∂L`` of the elastic
catenary (:func:`tether_dynamics.plant.quasi_static.end_tensions`, the plant's own
quasi-static solution) at the relative position and length of the plant's step. What the
platform's motion changes within the delay stays delayed.

The slope is closed-form (:func:`tether_dynamics.plant.quasi_static.tension_a_slope`): the
catenary's tension is differentiated in its stretched length L_s, and L_s in L implicitly
through the plant's stretch condition ``L_s = L (1 + T_mean/EA)``, with L_s from a few
Newton steps: the central difference of the plant's tension to about 1e-6, at a tenth of
its cost (it runs every reel step).

References:
    K. Talke, PhD thesis, UC San Diego, 2021, Sec. 3.1 (catenary), Eq. 7.42 (winch).
"""

from __future__ import annotations

import numpy as np

from tether_dynamics.plant.quasi_static import end_tensions
from tether_dynamics.plant.quasi_static import tension_a_slope
from tether_models.constants import GRAVITY

GUIDE = np.zeros(3)


class TetherStiffness:
    """``k = -∂T_A/∂L`` (N/m) of the elastic catenary between the guide way and the UAV end."""

    def __init__(self, linear_density: float, axial_stiffness: float, gravity: float = GRAVITY) -> None:
        self.linear_density = linear_density
        self.axial_stiffness = axial_stiffness
        self.gravity = gravity

    def tension(self, dr: float, dz: float, length: float) -> float:
        """Tension at the guide way (N) for ``length`` m of tether to the end at (Δr, Δz) m."""
        return end_tensions(GUIDE, np.array([dr, 0.0, dz]), length, self.linear_density, self.axial_stiffness,
                            self.gravity)[0]

    def __call__(self, dr: float, dz: float, length: float) -> float:
        """``-∂T_A/∂L`` (N/m) for ``length`` m of tether to the end at (Δr, Δz) m."""
        return -tension_a_slope(dr, dz, length, self.linear_density, self.axial_stiffness, self.gravity)
