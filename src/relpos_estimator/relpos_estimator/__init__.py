"""Simulated RTK dGPS and IMUs with faults, and the relative-altitude estimator (thesis Sec. 4.4, 6.2, 6.4)."""
