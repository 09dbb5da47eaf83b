"""Finite-element tether dynamics (thesis Chapters 7-9, Appendices C-D).

Linear and quadratic string elements (c1: the multiplier system of Eq. 8.44, solved in the
B-spline control points of the c1 space), pinned / point-mass /
rigid-body / prescribed-motion ends, compiled RK4 and velocity-Verlet time stepping,
optional drag, wind and Kelvin-Voigt damping, and per-step diagnostics.
"""
