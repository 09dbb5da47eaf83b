"""ArduPilot SITL as a node: the process runner, its parameter check, the sitl node."""
