"""Tether statics (thesis Ch. 3-4): the catenary between reel and UAV (Sec. 3.1.1), heave
robustness (Sec. 3.2), the flying-space sweep and fits (Sec. 3.2.1, Tables 3.1-3.2) and
the reference-length model (Sec. 4.1).

Plain numerical cores: no command-line or plotting code (that lives in
:mod:`tether_dynamics.commands`).
"""
