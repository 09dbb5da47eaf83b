"""Workspace validation profile (thesis Sec. 2.7.1, dashed path of Fig. 2.4).

The boundary of the ball-joint-limited workspace is shrunk towards the level pose to
25, 50, 75 and 90 % of its size; the four loops, joined one after another, form a roll-pitch
path through the whole workspace at zero heave, travelled at constant angular speed.
"""

from __future__ import annotations

import contourpy
import numpy as np
from scipy import ndimage

from psr_platform_sim.workspace import Region
from psr_platform_sim.workspace import WorkspaceTable
from tether_models.waves import MotionProfile


def region_boundary(table: WorkspaceTable, region: Region) -> np.ndarray:
    """Roll-pitch boundary (rad) of a workspace region, a closed loop (m, 2)."""
    mask = region.points.astype(float)
    lines = [np.asarray(line) for line in contourpy.contour_generator(z=mask).lines(0.5)]
    loop = max(lines, key=len)  # columns: (k, j) in grid indices
    coords = np.stack([loop[:, 1], loop[:, 0]])
    roll = ndimage.map_coordinates(table.roll, coords, order=1)
    pitch = ndimage.map_coordinates(table.pitch, coords, order=1)
    return np.stack([roll, pitch], axis=-1)


def workspace_profile(table: WorkspaceTable, region: Region, levels=(0.25, 0.5, 0.75, 0.9),
                      speed: float = np.radians(5.0), rate: float = 30.0) -> MotionProfile:
    """The validation path: scaled boundary loops joined in order, at ``speed`` rad/s.

    Args:
        table, region: the workspace whose boundary is followed.
        levels: sizes of the loops relative to the boundary.
        speed: roll-pitch path speed (rad/s).
        rate: sample rate (Hz).
    """
    boundary = region_boundary(table, region)
    path = [np.zeros((1, 2))]
    for level in levels:
        path.append(level * boundary)
    path.append(np.zeros((1, 2)))
    points = np.concatenate(path)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=-1))])
    keep = np.concatenate([[True], np.diff(arc) > 0])
    points, arc = points[keep], arc[keep]
    t = np.arange(0.0, arc[-1] / speed, 1.0 / rate)
    roll = np.interp(t * speed, arc, points[:, 0])
    pitch = np.interp(t * speed, arc, points[:, 1])
    return MotionProfile(t, np.zeros_like(t), roll, pitch, 'workspace-validation')
