"""Command-line and plotting code of tether_dynamics: ``tethersim catenary`` and
``tethersim fem``, their plots, and the Chapter 9 pendulum reproduction. The numerical
cores they drive live in :mod:`tether_dynamics.statics` and :mod:`tether_dynamics.fem`.
"""
