"""Path generation through the lookup table (thesis Sec. 2.6).

A commanded (heave, roll, pitch) becomes three slider heights: the nearest table point
w_n is found, the step from it to the desired point w_d is projected onto the three
slider directions of motion and added to the sliders (three-axis interpolation,
Eq. 2.17). Optionally a few Newton steps on the exact kinematics (Eq. 2.1-2.9) remove
the interpolation error. A common slider offset sets the heave. Slider velocities come
from fourth-order central differences and are limited in speed and acceleration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from psr_platform_sim.kinematics import Design
from psr_platform_sim.kinematics import solve_corners
from psr_platform_sim.kinematics import platform_pose
from psr_platform_sim.workspace import Region
from psr_platform_sim.workspace import WorkspaceTable

# Grid steps (dj, dk) and relative-height changes of moving slider 1, 2 or 3 by one step:
# raising slider 1 tilts the platform like lowering sliders 2 and 3 together.
_DIRECTIONS = (((-1, -1), (0.0, -1.0, -1.0)), ((1, 0), (0.0, 1.0, 0.0)), ((0, 1), (0.0, 0.0, 1.0)))


@dataclass
class SliderPath:
    """Slider heights along a profile and how well they reproduce it.

    Attributes:
        heights: slider heights above the rail base (m), (n, 3).
        inside: False where the command was clipped to the workspace.
        roll, pitch, heave: the commanded values after clipping (rad, rad, m).
    """

    heights: np.ndarray
    inside: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    heave: np.ndarray


class PathGenerator:
    """Turns commanded heave, roll, pitch into slider heights (Sec. 2.6).

    Args:
        table: lookup table of the mechanism (fine, ~1000 steps, for paths).
        region: usable part of the table (a workspace :class:`Region`).
        rail_base: height of the rail base below the level platform's neutral centre (m);
            slider heights are measured from it.
    """

    def __init__(self, table: WorkspaceTable, region: Region, rail_base: float) -> None:
        self.table = table
        self.region = region
        self.design: Design = table.design
        self.step = float(table.u2[1] - table.u2[0])
        points = np.argwhere(region.points)
        self._jk = points
        angles = np.stack([table.roll[region.points], table.pitch[region.points]], axis=-1)
        self._tree = cKDTree(angles)
        level, _, _ = solve_corners(self.design, np.zeros((1, 3)))
        self.neutral_centre = float(platform_pose(level).p[0, 2])
        self.rail_base = rail_base

    def nearest(self, roll: np.ndarray, pitch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid indices (j, k) of the nearest usable table point w_n."""
        _, index = self._tree.query(np.stack([roll, pitch], axis=-1))
        return self._jk[index, 0], self._jk[index, 1]

    def interpolate(self, roll: np.ndarray, pitch: np.ndarray) -> np.ndarray:
        """Relative slider heights (slider 1 at 0) for roll, pitch by Eq. 2.17, shape (n, 3).

        Eq. 2.17 as printed divides the projection by |w_m - w_n| once; the step
        fraction needs |w_m - w_n|^2 (the printed form is not dimensionless), and the
        neighbour w_m is taken on the side of w_d so that the projection is positive.
        """
        roll, pitch = np.atleast_1d(roll).astype(float), np.atleast_1d(pitch).astype(float)
        t = self.table
        n = t.steps
        j, k = self.nearest(roll, pitch)
        wd = np.stack([roll, pitch], axis=-1)
        wn = np.stack([t.roll[j, k], t.pitch[j, k]], axis=-1)
        u = t.heights(j, k)
        delta = wd - wn
        total = np.zeros_like(u)
        for (dj, dk), change in _DIRECTIONS:
            best = np.zeros(roll.shape)
            best_sign = np.zeros(roll.shape)
            for sign in (1, -1):
                jm, km = j + sign * dj, k + sign * dk
                ok = (jm >= 0) & (jm < n) & (km >= 0) & (km < n)
                jm, km = np.clip(jm, 0, n - 1), np.clip(km, 0, n - 1)
                ok &= self.region.points[jm, km]
                wm = np.stack([t.roll[jm, km], t.pitch[jm, km]], axis=-1) - wn
                norm2 = np.maximum(np.einsum('...k,...k->...', wm, wm), 1e-300)
                fraction = np.einsum('...k,...k->...', delta, wm) / norm2  # Eq. 2.17 projection
                take = ok & (fraction > best)
                best = np.where(take, fraction, best)
                best_sign = np.where(take, sign, best_sign)
            total += (best * best_sign)[:, None] * np.asarray(change) * self.step
        return u + 2.0 / 3.0 * total  # Eq. 2.17

    def refine(self, relative: np.ndarray, roll: np.ndarray, pitch: np.ndarray,
               iterations: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """Newton steps on the exact kinematics from Eq. 2.17's relative heights.

        Returns the refined relative heights and the remaining roll-pitch error (rad).
        """
        u = relative[:, 1:].copy()
        eps = 1e-6 * self.design.r
        target = np.stack([roll, pitch], axis=-1)
        for iteration in range(iterations + 1):
            base = self._angles(u)
            error = base - target
            if iteration == iterations:
                break
            jac = np.empty(u.shape + (2,))
            for m in range(2):
                shifted = u.copy()
                shifted[:, m] += eps
                jac[..., m] = (self._angles(shifted) - base) / eps
            ok = np.abs(np.linalg.det(jac)) > 1e-12
            jac[~ok] = np.eye(2)
            step = np.linalg.solve(jac, -error[..., None])[..., 0]
            u = np.where(ok[:, None], u + step, u)
        refined = np.concatenate([np.zeros((u.shape[0], 1)), u], axis=-1)
        return refined, np.linalg.norm(error, axis=-1)

    def _angles(self, u: np.ndarray) -> np.ndarray:
        heights = np.concatenate([np.zeros((u.shape[0], 1)), u], axis=-1)
        corners, _, _ = solve_corners(self.design, heights)
        pose = platform_pose(corners)
        return np.stack([pose.roll, pose.pitch], axis=-1)

    def in_region(self, relative: np.ndarray) -> np.ndarray:
        """True where relative slider heights fall in (or on the edge of) a usable table cell."""
        n = self.table.steps
        position = (relative[:, 1:] - self.table.u2[0]) / self.step
        inside = np.zeros(relative.shape[0], dtype=bool)
        for nudge in ((-1e-7, -1e-7), (-1e-7, 1e-7), (1e-7, -1e-7), (1e-7, 1e-7)):
            jk = np.floor(position + np.asarray(nudge)).astype(int)
            ok = np.all((jk >= 0) & (jk < n - 1), axis=-1)
            jk = np.clip(jk, 0, n - 2)
            inside |= ok & self.region.cells[jk[:, 0], jk[:, 1]]
        return inside

    def sliders(self, heave: np.ndarray, roll: np.ndarray, pitch: np.ndarray,
                exact: bool = True, heave_limit: float = np.inf) -> SliderPath:
        """Slider heights for a commanded profile, clipped to the workspace.

        Args:
            heave: commanded platform-centre heave from the neutral height (m).
            roll, pitch: commanded angles (rad), Eq. 2.7-2.8 convention.
            exact: refine Eq. 2.17 by Newton steps on the exact kinematics.
            heave_limit: symmetric heave range of the rails (m).
        """
        heave = np.clip(np.asarray(heave, dtype=float), -heave_limit, heave_limit)
        heave_ok = np.abs(np.asarray(heave)) < heave_limit
        roll, pitch = np.asarray(roll, dtype=float).copy(), np.asarray(pitch, dtype=float).copy()
        relative = self.interpolate(roll, pitch)
        if exact:
            relative, error = self.refine(relative, roll, pitch)
            inside = self.in_region(relative) & (error < 1e-7)
        else:
            inside = self.in_region(relative)
        if not inside.all():
            j, k = self.nearest(roll[~inside], pitch[~inside])
            relative[~inside] = self.table.heights(j, k)
            roll[~inside], pitch[~inside] = self.table.roll[j, k], self.table.pitch[j, k]
        corners, _, _ = solve_corners(self.design, relative)
        centre_z = platform_pose(corners).p[:, 2]
        # A common offset moves the platform straight up: it sets the heave exactly.
        offset = self.neutral_centre + heave - centre_z
        heights = relative + offset[:, None] - self.rail_base
        return SliderPath(heights, inside & heave_ok, roll, pitch, heave)


def central_velocity(positions: np.ndarray, dt: float) -> np.ndarray:
    """Velocity by the fourth-order central difference (second order at the ends), axis 0."""
    v = np.gradient(positions, dt, axis=0, edge_order=2)
    if positions.shape[0] >= 5:
        v[2:-2] = (-positions[4:] + 8.0 * positions[3:-1] - 8.0 * positions[1:-3] + positions[:-4]) / (12.0 * dt)
    return v


def limit_motion(positions: np.ndarray, dt: float, max_speed: float, max_accel: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Follow commanded slider positions with bounded speed and acceleration.

    Each tick the slider speed is set to reach the next command, limited to
    ``max_speed`` and to a change of ``max_accel * dt`` from the previous speed.

    Returns the achieved positions, the speeds held over each tick, and the number of
    ticks where a limit was active.
    """
    achieved = np.empty_like(positions)
    speeds = np.zeros_like(positions)
    achieved[0] = positions[0]
    speed = np.zeros(positions.shape[1:])
    limited = 0
    for i in range(positions.shape[0] - 1):
        wanted = (positions[i + 1] - achieved[i]) / dt
        bounded = np.clip(wanted, speed - max_accel * dt, speed + max_accel * dt)
        bounded = np.clip(bounded, -max_speed, max_speed)
        limited += int(np.any(np.abs(bounded - wanted) > 1e-12))
        speed = bounded
        speeds[i] = speed
        achieved[i + 1] = achieved[i] + speed * dt
    speeds[-1] = speed
    return achieved, speeds, limited
