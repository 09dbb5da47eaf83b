"""Shared plumbing of the tethersim nodes: parameter specifications with ranges, named QoS profiles, the node main loop."""
