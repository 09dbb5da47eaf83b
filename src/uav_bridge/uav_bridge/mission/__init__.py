"""The mission: its phase logic, the node that steps it, the flight and mission reports."""
