"""The UAV's end of the graph: the MAVLink bridge to ArduPilot and the mission logic."""
