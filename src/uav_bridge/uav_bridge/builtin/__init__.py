"""The built-in UAV: multirotor dynamics, its attitude and position control, the node."""
