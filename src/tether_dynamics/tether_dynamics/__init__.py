"""Tether statics (catenary, heave robustness, reference length) and dynamics (finite elements) for tethersim."""
