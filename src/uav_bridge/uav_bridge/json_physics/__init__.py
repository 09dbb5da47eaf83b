"""ArduPilot's JSON physics backend.

The wire protocol, the quadrotor model and its motors, the server and the node, the SITL
flight in one process and its tether-flight report.
"""
