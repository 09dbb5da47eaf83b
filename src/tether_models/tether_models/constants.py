"""Physical constants shared by every model, so each has one value everywhere."""

GRAVITY = 9.81
"""Gravitational acceleration, m/s² (the value of the thesis's models); it acts along -z of ``world`` (ENU)."""
