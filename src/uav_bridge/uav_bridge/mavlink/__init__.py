"""The MAVLink link to ArduPilot: transport, session, autopilot state, telemetry in ENU/FLU, the bridge node."""
