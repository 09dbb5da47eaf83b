"""Bringup of tethersim scenes: sim clock, recorder, replay, bag tools, scenes and reports."""
