"""Finite-element tether dynamics (thesis Chapters 7-9, Appendices C-D).

Linear and quadratic (c1 by Lagrange multipliers) string elements, pinned / point-mass /
rigid-body / prescribed-motion ends, compiled RK4 and velocity-Verlet time stepping,
optional drag, wind and Kelvin-Voigt damping, and per-step diagnostics.
"""
