"""Errors of the finite-element tether model."""

from __future__ import annotations


class FemError(Exception):
    """A finite-element model was set up with invalid data."""


class DivergenceError(FemError):
    """A time integration left the physical range (NaN, runaway strain).

    Attributes:
        time: float
            Simulated time (s) of the first step found bad.
        element: int
            Index of the element where it was found (-1 if not tied to one).
        strain: float
            Largest strain found (may be nan).
    """

    def __init__(self, time: float, element: int, strain: float, cause: str) -> None:
        self.time = time
        self.element = element
        self.strain = strain
        where = f'element {element}' if element >= 0 else 'the end body'
        msg = (f'simulation diverged at t = {time:.6g} s in {where} '
               f'(strain {strain:.3g}); likely cause: {cause}')
        super().__init__(msg)
