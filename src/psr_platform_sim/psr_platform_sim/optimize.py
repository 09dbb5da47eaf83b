"""Design parameter study of the 3-PSR mechanism (thesis Sec. 2.5).

Arm length l and platform edge d run from 50 % to 150 % of the tower radius r in 2.5 %
steps (41 x 41 designs); each design's 200 x 200 workspace grid is solved (Sec. 2.4) and
the usable roll-pitch area measured with the hinge limit of Eq. 2.16, then again for
every ball-joint mounting angle gamma from 20 to 45 deg with the 30 deg joint limit
(Sec. 2.5.1). Designs whose workspace falls apart into several pieces are discarded.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from psr_platform_sim.kinematics import Design
from psr_platform_sim.workspace import ball_region
from psr_platform_sim.workspace import build_table
from psr_platform_sim.workspace import nominal_region

TABLE_2_2 = (
    (4551.9, 0.825, 1.325), (4547.1, 0.85, 1.3), (4543.1, 0.875, 1.275),
    (4540.9, 0.9, 1.25), (4536.8, 0.925, 1.225), (4535.7, 1.05, 1.1),
)
"""Thesis Table 2.2: area (deg^2), l, d of the top six designs."""

TABLE_2_3 = (
    (2816.5, 0.975, 1.15, 30), (2813.9, 1.0, 1.075, 32), (2812.7, 1.0, 1.125, 30),
    (2811.5, 0.95, 1.075, 34), (2809.2, 1.0, 1.05, 33), (2805.1, 1.0, 1.1, 31),
)
"""Thesis Table 2.3: area (deg^2), l, d, gamma (deg) with the ball-joint limit."""


@dataclass(frozen=True)
class StudySettings:
    """Grid of the study; the defaults are the thesis's (Sec. 2.4-2.5)."""

    ratio_low: float = 0.5
    ratio_high: float = 1.5
    ratio_step: float = 0.025
    slider_steps: int = 200
    gamma_low_deg: float = 20.0
    gamma_high_deg: float = 45.0
    gamma_step_deg: float = 1.0

    @property
    def ratios(self) -> np.ndarray:
        """l/r and d/r values."""
        count = int(round((self.ratio_high - self.ratio_low) / self.ratio_step)) + 1
        return np.round(np.linspace(self.ratio_low, self.ratio_high, count), 6)

    @property
    def gammas_deg(self) -> np.ndarray:
        """Ball-joint mounting angles (deg)."""
        count = int(round((self.gamma_high_deg - self.gamma_low_deg) / self.gamma_step_deg)) + 1
        return np.linspace(self.gamma_low_deg, self.gamma_high_deg, count)

    @property
    def solves(self) -> int:
        """Number of Newton solves of the whole study."""
        return self.ratios.size**2 * self.slider_steps**2


QUICK = StudySettings(ratio_step=0.05, slider_steps=100)
"""Coarse study: 5 % steps, 100 x 100 slider grid."""


@dataclass
class StudyResult:
    """Areas of every design of the study (deg^2); index [i_l, i_d] (and [.., i_gamma]).

    ``components`` counts the pieces of the nominal workspace; ``ball_components`` those
    of the ball-joint-limited one.
    """

    settings: StudySettings
    nominal_area: np.ndarray
    components: np.ndarray
    ball_area: np.ndarray
    ball_components: np.ndarray
    seconds: float

    def top_nominal(self, count: int = 6) -> list[tuple[float, float, float]]:
        """Best connected designs without the ball-joint limit: (area, l, d)."""
        area = np.where(self.components == 1, self.nominal_area, -1.0)
        order = np.argsort(area, axis=None)[::-1][:count]
        ratios = self.settings.ratios
        return [(float(area.flat[i]), *(float(ratios[v]) for v in np.unravel_index(i, area.shape)))
                for i in order]

    def top_ball(self, count: int = 6) -> list[tuple[float, float, float, float]]:
        """Best connected designs with the ball-joint limit, best gamma each: (area, l, d, gamma deg)."""
        area = np.where(self.ball_components == 1, self.ball_area, -1.0)
        best = area.argmax(axis=-1)
        best_area = np.take_along_axis(area, best[..., None], axis=-1)[..., 0]
        order = np.argsort(best_area, axis=None)[::-1][:count]
        ratios, gammas = self.settings.ratios, self.settings.gammas_deg
        rows = []
        for i in order:
            il, idd = np.unravel_index(i, best_area.shape)
            rows.append((float(best_area[il, idd]), float(ratios[il]), float(ratios[idd]),
                         float(gammas[best[il, idd]])))
        return rows

    def save(self, path) -> None:
        """Write the result arrays to an .npz file."""
        np.savez(path, ratios=self.settings.ratios, gammas_deg=self.settings.gammas_deg,
                 nominal_area=self.nominal_area, components=self.components,
                 ball_area=self.ball_area, ball_components=self.ball_components,
                 slider_steps=self.settings.slider_steps, seconds=self.seconds)


def evaluate_design(design: Design, settings: StudySettings) -> tuple[float, int, np.ndarray, np.ndarray]:
    """Nominal area, its piece count, and area and piece count per gamma for one design."""
    table = build_table(design, settings.slider_steps)
    nominal = nominal_region(table)
    areas = np.empty(settings.gammas_deg.size)
    pieces = np.empty(settings.gammas_deg.size, dtype=int)
    for g, gamma in enumerate(np.radians(settings.gammas_deg)):
        region = ball_region(table, gamma)
        areas[g] = region.area
        pieces[g] = region.components
    return nominal.area, nominal.components, areas, pieces


def run_study(settings: StudySettings, progress: Callable[[int, int, float], None] | None = None,
              arm_ratios: np.ndarray | None = None) -> StudyResult:
    """Evaluate every (l, d) of the study; ``progress(done, total, elapsed_s)`` after each design.

    ``arm_ratios`` restricts the arm lengths (a fraction of the study, for timing).
    """
    ratios = settings.ratios
    arm_ratios = ratios if arm_ratios is None else np.asarray(arm_ratios)
    n, g = ratios.size, settings.gammas_deg.size
    nominal = np.full((n, n), np.nan)
    components = np.zeros((n, n), dtype=int)
    ball = np.full((n, n, g), np.nan)
    ball_components = np.zeros((n, n, g), dtype=int)
    total = arm_ratios.size * n
    start = time.perf_counter()
    done = 0
    for l_ratio in arm_ratios:
        il = int(np.argmin(np.abs(ratios - l_ratio)))
        for idd, d_ratio in enumerate(ratios):
            design = Design(r=1.0, l=float(l_ratio), d=float(d_ratio))
            nominal[il, idd], components[il, idd], ball[il, idd], ball_components[il, idd] = (
                evaluate_design(design, settings))
            done += 1
            if progress is not None:
                progress(done, total, time.perf_counter() - start)
    return StudyResult(settings, nominal, components, ball, ball_components, time.perf_counter() - start)
