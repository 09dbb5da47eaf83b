"""Campaigns: Monte Carlo sweeps of tethersim scenes on Ray."""
