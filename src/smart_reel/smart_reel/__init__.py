"""Smart reel of the tethered UAV-USV team (thesis Sec. 4.1-4.3, 5.1, 5.5, 6.1-6.2).

Plain-Python cores, no rclpy: :mod:`motor` (DC servo motor), :mod:`spool` (drum layers,
encoder), :mod:`winch` (motor, gearbox, drum, friction and stiction against the tether
pull), :mod:`sensors` (guide arm, tension from current), :mod:`scheduler` (Eq. 4.1 low-pass
filter and its Schmitt-trigger schedule), :mod:`controller` (catenary-model PD and taut
controllers), :mod:`safety`, :mod:`reel` (one stepping object for node, tests and tuning),
:mod:`tuning` (the gain procedure). The node :mod:`reel_node` is a thin wrapper.
"""
