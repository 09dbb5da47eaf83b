"""The UAV's end of the graph, by subsystem.

``mavlink`` (the link to ArduPilot), ``sitl`` (ArduPilot SITL as a node), ``json_physics``
(ArduPilot's JSON physics backend), ``builtin`` (the built-in UAV) and ``mission``.
"""
