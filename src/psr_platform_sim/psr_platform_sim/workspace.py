"""Roll-pitch workspace lookup table of the 3-PSR mechanism (thesis Sec. 2.4-2.5).

Slider 1 is held at 2.5 r while sliders 2 and 3 sweep 0..5 r; every combination is
solved (Eq. 2.1-2.3), its pose taken (Eq. 2.4-2.9) and the physical constraints applied
(Eq. 2.14-2.16). A common slider offset only raises the platform, so the table covers
every pose of the mechanism at every heave.

The usable workspace is the part of the slider grid reachable from the level pose
without crossing a fold of the map (s2, s3) -> (roll, pitch): the thesis cut the
"kinematic lock" regions where the slider curves wrap back with a hand-drawn polygon
(Fig. 2.3b); here they are cut where the Jacobian of that map changes sign, which needs
no hand-drawn input. Its area is the sum of the grid cells' images (deg^2).
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import asdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage

from psr_platform_sim.kinematics import HINGE_LIMIT
from psr_platform_sim.kinematics import Design
from psr_platform_sim.kinematics import physical_margins
from psr_platform_sim.kinematics import platform_pose
from psr_platform_sim.kinematics import rail_directions
from psr_platform_sim.kinematics import slider_points
from psr_platform_sim.kinematics import solve_corners

TABLE_VERSION = 1


def default_cache_dir() -> Path:
    """Cache directory for tables: $TETHERSIM_CACHE or ~/.cache/tethersim, then /psr."""
    root = os.environ.get('TETHERSIM_CACHE') or Path.home() / '.cache' / 'tethersim'
    return Path(root) / 'psr'


@dataclass
class WorkspaceTable:
    """Poses of the mechanism over a grid of relative slider heights (Sec. 2.4).

    Heights are relative to slider 1: ``u2[j]`` and ``u3[k]`` are slider 2's and 3's
    heights minus slider 1's. Pose arrays have shape (n, n) indexed [j, k].

    Attributes:
        design: the mechanism.
        u2, u3: relative slider heights (m), shape (n,).
        roll, pitch, yaw: Eq. 2.7-2.9 (rad).
        centre: platform centre relative to (0, 0, slider 1's height) (m), (n, n, 3).
        feasible: solved and inside Eq. 2.14-2.15.
        hinge_margin: smallest normalized <s_i - c_i, z'>/l (Eq. 2.16).
        arm_axial, arm_radial: arm vector s_i - c_i along z and along t_i (m), (n, n, 3);
            with them the ball-joint angle for any gamma is cheap (Eq. 2.11).
    """

    design: Design
    u2: np.ndarray
    u3: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray
    centre: np.ndarray
    feasible: np.ndarray
    hinge_margin: np.ndarray
    arm_axial: np.ndarray
    arm_radial: np.ndarray

    @property
    def steps(self) -> int:
        """Number of grid steps per slider axis."""
        return self.u2.size

    def heights(self, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        """Slider heights (..., 3) of grid points [j, k], slider 1 at zero."""
        j, k = np.broadcast_arrays(np.asarray(j), np.asarray(k))
        return np.stack([np.zeros(j.shape), self.u2[j], self.u3[k]], axis=-1)

    def ball_ok(self, gamma: float) -> np.ndarray:
        """True where every ball-joint angle (Eq. 2.11) is within the design's limit."""
        cosine = (np.cos(gamma) * self.arm_axial + np.sin(gamma) * self.arm_radial) / self.design.l
        return cosine.min(axis=-1) >= np.cos(self.design.ball_limit)

    def save(self, path: Path) -> None:
        """Write the table to an .npz file."""
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix('.tmp.npz')
        np.savez(tmp, version=TABLE_VERSION, design=np.array(list(asdict(self.design).values())),
                 u2=self.u2, u3=self.u3, roll=self.roll, pitch=self.pitch, yaw=self.yaw,
                 centre=self.centre, feasible=self.feasible, hinge_margin=self.hinge_margin,
                 arm_axial=self.arm_axial, arm_radial=self.arm_radial)
        tmp.replace(path)

    @classmethod
    def load(cls, path: Path) -> WorkspaceTable:
        """Read a table written by :meth:`save`."""
        with np.load(path) as data:
            if int(data['version']) != TABLE_VERSION:
                raise ValueError(f'{path}: table version {int(data["version"])}, expected {TABLE_VERSION}')
            design = Design(*(float(v) for v in data['design']))
            fields = {name: data[name] for name in (
                'u2', 'u3', 'roll', 'pitch', 'yaw', 'centre', 'feasible', 'hinge_margin',
                'arm_axial', 'arm_radial')}
        return cls(design=design, **fields)


def build_table(design: Design, steps: int = 200, span: float = 5.0) -> WorkspaceTable:
    """Solve the workspace grid (Sec. 2.4): slider 1 at span/2 r, sliders 2, 3 over 0..span r.

    Args:
        design: the mechanism.
        steps: grid points per slider axis (200 in the thesis's study, ~1000 for paths).
        span: slider range in units of r.
    """
    u = (np.linspace(0.0, span, steps) - span / 2.0) * design.r
    heights = np.stack(np.broadcast_arrays(0.0, u[:, None], u[None, :]), axis=-1)
    corners, _, converged = solve_corners(design, heights)
    pose = platform_pose(corners)
    tower, hinge = physical_margins(design, heights, corners)
    arm = slider_points(design, heights) - corners
    return WorkspaceTable(
        design=design, u2=u, u3=u.copy(), roll=pose.roll, pitch=pose.pitch, yaw=pose.yaw,
        centre=pose.p, feasible=converged & (tower >= 0.0) & (hinge >= 0.0),
        hinge_margin=hinge, arm_axial=arm[..., 2],
        arm_radial=np.einsum('...ik,ik->...i', arm, rail_directions()))


def cached_table(design: Design, steps: int = 200, cache_dir: Path | None = None) -> WorkspaceTable:
    """Return the table for ``design``, loading it from the cache or building and saving it."""
    cache_dir = default_cache_dir() if cache_dir is None else Path(cache_dir)
    key = hashlib.sha1(repr((TABLE_VERSION, design.r, design.l, design.d, steps)).encode()).hexdigest()[:16]
    path = cache_dir / f'table-{key}.npz'
    if path.exists():
        table = WorkspaceTable.load(path)
        return WorkspaceTable(**{**table.__dict__, 'design': design})
    table = build_table(design, steps)
    table.save(path)
    return table


def cell_areas(table: WorkspaceTable) -> np.ndarray:
    """Signed roll-pitch areas (deg^2) of the grid cells' two triangles, shape (n-1, n-1, 2)."""
    w = np.degrees(np.stack([table.roll, table.pitch], axis=-1))
    a, b, c, d = w[:-1, :-1], w[1:, :-1], w[:-1, 1:], w[1:, 1:]

    def signed(p, q, s):
        return 0.5 * ((q[..., 0] - p[..., 0]) * (s[..., 1] - p[..., 1])
                      - (q[..., 1] - p[..., 1]) * (s[..., 0] - p[..., 0]))

    return np.stack([signed(a, b, c), signed(d, c, b)], axis=-1)


@dataclass(frozen=True)
class Region:
    """The usable workspace: fold-free cells connected to the level pose.

    Attributes:
        cells: mask of grid cells (n-1, n-1) in the region.
        points: mask of grid points (n, n) at the corners of those cells.
        area: roll-pitch area (deg^2).
        components: number of separate fold-free pieces (of > 1 % of the region's cells)
            among the allowed cells; more than one means a disjoint workspace.
    """

    cells: np.ndarray
    points: np.ndarray
    area: float
    components: int


def usable_region(table: WorkspaceTable, allowed: np.ndarray, areas: np.ndarray | None = None) -> Region:
    """Workspace region of the points in ``allowed`` (Sec. 2.5), without kinematic lock.

    A cell counts when its four corners are allowed and both its triangles keep the
    orientation of the level pose's cell; the region is the connected set of such cells
    holding the level pose.
    """
    areas = cell_areas(table) if areas is None else areas
    n = table.steps
    mid = n // 2 - 1 if n % 2 == 0 else n // 2
    sign = np.sign(areas[mid, mid].sum())
    corners_ok = allowed[:-1, :-1] & allowed[1:, :-1] & allowed[:-1, 1:] & allowed[1:, 1:]
    cells = corners_ok & (np.sign(areas[..., 0]) == sign) & (np.sign(areas[..., 1]) == sign) & (sign != 0)
    labels, count = ndimage.label(cells)
    label = labels[mid, mid]
    if label == 0:
        empty = np.zeros_like(cells)
        return Region(empty, np.zeros_like(allowed), 0.0, 0)
    region = labels == label
    sizes = np.bincount(labels.ravel())[1:]
    components = int(np.sum(sizes > 0.01 * sizes[label - 1]))
    points = np.zeros_like(allowed)
    for dj in (0, 1):
        for dk in (0, 1):
            points[dj:n - 1 + dj, dk:n - 1 + dk] |= region
    area = float(np.abs(areas[region]).sum())
    return Region(region, points, area, components)


def nominal_region(table: WorkspaceTable) -> Region:
    """Workspace with Eq. 2.14 and the hinge limit of Eq. 2.16 (Sec. 2.5)."""
    return usable_region(table, table.feasible & (table.hinge_margin >= HINGE_LIMIT))


def ball_region(table: WorkspaceTable, gamma: float | None = None) -> Region:
    """Workspace that also keeps every ball joint within its limit (Sec. 2.5.1)."""
    gamma = table.design.gamma if gamma is None else gamma
    allowed = table.feasible & (table.hinge_margin >= HINGE_LIMIT) & table.ball_ok(gamma)
    return usable_region(table, allowed)
