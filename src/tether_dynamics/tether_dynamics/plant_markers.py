"""The 3-D view of the plant as a visualization_msgs/MarkerArray (no rclpy import).

Every marker is in frame ``world`` with the plant step's stamp, so Foxglove and RViz show
the scene without any transform: Foxglove's 3-D panel registers each marker's
``header.frame_id`` as a coordinate frame when the message arrives (its renderer scrapes
``markers[].header.frame_id``), picks a root frame as the display frame, and places a marker
whose frame is the display frame with the identity; a marker in ``boat`` or ``uav`` would
need a transform path to the display frame at the marker's ``header.stamp``, which nobody
publishes. Markers keep their namespace and id from message to message and have no lifetime,
so each new array replaces the previous shapes.

Namespaces: ``tether`` (line through the nodes), ``reference`` (the catenary of the
reference length between the same ends, Eq. 3.2 with Eq. 4.4/4.5), ``reel`` (drum at the
guide way), ``platform`` (deck plate at the reel mount, in the boat's attitude), ``uav``
(attachment point), ``lowest_point`` (red when the tether fouls).
"""

from __future__ import annotations

import math

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point
from visualization_msgs.msg import Marker
from visualization_msgs.msg import MarkerArray

from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.geometry_fill import fill_xyz
from tether_dynamics.plant import quasi_static
from tether_dynamics.statics.catenary import GRAVITY
from tether_dynamics.statics.catenary import THESIS_LINEAR_DENSITY
from tether_dynamics.statics.reference_length import reference_length

FRAME = 'world'
REFERENCE_POINTS = 41
UPRIGHT = np.array([0.0, 0.0, 0.0, 1.0])
COLORS = {
    'tether': (1.0, 0.55, 0.0, 1.0),
    'reference': (0.2, 0.8, 0.3, 0.7),
    'reel': (0.3, 0.3, 0.35, 1.0),
    'platform': (0.6, 0.6, 0.65, 0.9),
    'uav': (0.1, 0.4, 0.9, 1.0),
    'lowest_point': (1.0, 0.9, 0.1, 1.0),
    'fouling': (0.9, 0.1, 0.1, 1.0),
}


def reference_shape(guide_way: np.ndarray, uav: np.ndarray, n: int = REFERENCE_POINTS) -> np.ndarray:
    """Return ``(n, 3)`` points of the catenary of the reference length from guide way to UAV (world, m).

    The reference length is that of the relative position (Eq. 4.4/4.5, with the safeguards of
    :func:`tether_dynamics.statics.reference_length.reference_length`); its catenary (Eq. 3.2,
    inextensible) hangs in the vertical plane through both ends.
    """
    a, b = np.asarray(guide_way, dtype=float), np.asarray(uav, dtype=float)
    d = b - a
    length = reference_length(float(np.hypot(d[0], d[1])), float(d[2])).length
    return quasi_static.shape_points(a, b, length, THESIS_LINEAR_DENSITY, math.inf, GRAVITY, n)


def _marker(ns: str, kind: int, color: tuple[float, float, float, float],
            scale: tuple[float, float, float]) -> Marker:
    marker = Marker()
    marker.header.frame_id = FRAME
    marker.ns = ns
    marker.id = 0
    marker.type = kind
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = color
    marker.scale.x, marker.scale.y, marker.scale.z = scale
    return marker


def _place(marker: Marker, position: np.ndarray, quaternion: np.ndarray) -> None:
    fill_vector(marker.pose.position, position)
    fill_quaternion(marker.pose.orientation, quaternion)


class SceneMarkers:
    """The scene's markers for the plant's steps: one MarkerArray, refilled at each call of :meth:`fill`
    (``publish()`` serialises it at once, so the node may refill it for the next step).
    """

    def __init__(self) -> None:
        self.tether = _marker('tether', Marker.LINE_STRIP, COLORS['tether'], (0.03, 0.0, 0.0))
        self.reference = _marker('reference', Marker.LINE_STRIP, COLORS['reference'], (0.015, 0.0, 0.0))
        self.reel = _marker('reel', Marker.CYLINDER, COLORS['reel'], (0.25, 0.25, 0.12))
        self.platform = _marker('platform', Marker.CUBE, COLORS['platform'], (0.46, 0.40, 0.03))
        self.uav = _marker('uav', Marker.SPHERE, COLORS['uav'], (0.3, 0.3, 0.12))
        self.lowest = _marker('lowest_point', Marker.SPHERE, COLORS['lowest_point'], (0.08, 0.08, 0.08))
        self.array = MarkerArray(markers=[self.tether, self.reference, self.reel, self.platform, self.uav,
                                          self.lowest])

    def fill(self, stamp: Time, nodes: np.ndarray, reel_mount: np.ndarray, boat_quaternion: np.ndarray,
             guide_way: np.ndarray, uav: np.ndarray, lowest_point: np.ndarray, fouling: bool) -> MarkerArray:
        """The scene's markers for one plant step.

        Args:
            stamp: the plant step's sim time.
            nodes: ``(n, 3)`` tether points from the reel end to the UAV end, world (m).
            reel_mount: reel mount position (/platform/reel_pose), world (m).
            boat_quaternion: attitude of ``boat`` in ``world`` (x, y, z, w).
            guide_way, uav: tether ends, world (m).
            lowest_point: lowest point of the tether, world (m).
            fouling: the plant's fouling flag (colours the lowest point red).
        """
        for marker in self.array.markers:
            marker.header.stamp = stamp
        fill_xyz(self.tether.points, nodes, Point)
        fill_xyz(self.reference.points, reference_shape(guide_way, uav), Point)
        _place(self.reel, guide_way, boat_quaternion)
        _place(self.platform, reel_mount, boat_quaternion)
        _place(self.uav, uav, UPRIGHT)
        _place(self.lowest, lowest_point, UPRIGHT)
        color = self.lowest.color
        color.r, color.g, color.b, color.a = COLORS['fouling' if fouling else 'lowest_point']
        return self.array
