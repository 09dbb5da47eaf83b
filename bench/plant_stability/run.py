"""How close to the stable-step estimate the moving-reel FEM plant stays stable (issue 36).

A hard case of the held-out class (a stiff, light tether on a moving reel): 30 m of tether,
EA 30 kN, mu 0.015 kg/m, between a guide way heaving +-1 m with a 3 s period and a prescribed
UAV end that is driven 4 m sideways in 0.8 s, while the reel pays out and reels in at 1.5 m/s.
For linear (N = 10, 30) and quadratic (N = 20) elements, without and with internal damping
(Kelvin-Voigt c = 3 N s), the step is scanned from 0.3 to 0.9 of the estimate
:func:`tether_dynamics.plant.fem_reel.stable_step`; each run reports the peak tension at the
UAV end, the largest energy-balance residual over the run as a share of the energy throughput
so far, and whether the plant stopped it (:class:`PlantDivergenceError`).

Run:  ./tethersim-env python bench/plant_stability/run.py [--quick] [--out DIR]
Writes scan.csv and summary.txt.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np

from tether_dynamics.plant import PlantConfig, PlantInputs, ReelConfig, TetherPlant, UavConfig
from tether_dynamics.plant.fem_reel import PlantDivergenceError, stable_step

LENGTH, EA, MU, RADIUS = 40.0, 4.0e4, 0.01, 0.05
UAV = np.array([28.0, 0.0, 28.0])
CALL = 0.01
DURATION = 6.0
CASES = (('linear', 10, 0.0), ('linear', 10, 3.0), ('linear', 30, 0.0), ('linear', 30, 3.0),
         ('quadratic', 20, 0.0), ('quadratic', 20, 3.0))
FRACTIONS = (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)


def _smooth(t: float, start: float, duration: float) -> tuple[float, float]:
    """Half-cosine from 0 (before start) to 1 (after start + duration) and its rate."""
    u = min(max((t - start) / duration, 0.0), 1.0)
    rate = 0.5 * math.pi / duration * math.sin(math.pi * u) if 0.0 < u < 1.0 else 0.0
    return 0.5 - 0.5 * math.cos(math.pi * u), rate


def inputs_at(t: float) -> PlantInputs:
    """Guide way heaving +-1 m (3 s period), the UAV end 4 m sideways over 1.0-1.8 s, payout at
    1.5 m/s over 0.5-2.5 s and reel-in at 1.5 m/s over 3.0-5.0 s (0.2 s ramps).
    """
    w = 2.0 * math.pi / 4.0
    side, side_rate = _smooth(t, 1.0, 0.6)
    speed = 2.5 * (_smooth(t, 0.5, 0.2)[0] - _smooth(t, 2.3, 0.2)[0] - _smooth(t, 3.0, 0.2)[0]
                   + _smooth(t, 4.8, 0.2)[0])
    return PlantInputs(platform_position=np.array([0.0, 0.0, 1.5 * math.sin(w * t)]),
                       platform_velocity=np.array([0.0, 0.0, 1.5 * w * math.cos(w * t)]),
                       uav_position=UAV + [0.0, 4.0 * side, 0.0], uav_velocity=np.array([0.0, 4.0 * side_rate, 0.0]),
                       spool_rate=speed / RADIUS)


def config(fidelity: str, n: int, damping: float, fraction: float) -> PlantConfig:
    """The hard case's plant at ``fraction`` of the stable-step estimate."""
    effects = {'effects': ('damping',), 'damping': damping} if damping > 0.0 else {}
    base = {'fidelity': fidelity, 'elements': n, 'initial_length': LENGTH, 'ea': EA, 'mass_per_length': MU,
            'guide_way_offset': (0.0, 0.0, 0.0),
            'reel': ReelConfig(input='spool_rate', spool_radius=RADIUS, max_length=60.0, total_length=80.0),
            'uav': UavConfig(mode='prescribed', attach_offset=(0.0, 0.0, 0.0)), **effects}
    return PlantConfig(dt=fraction * stable_step(PlantConfig(dt=1.0, **base)), **base)


def run(cfg: PlantConfig, duration: float = DURATION) -> dict[str, float | str]:
    """Peak UAV-end tension (N), the largest |residual| / throughput of the energy balance and
    how the run ended ('ok' or the divergence error's message).
    """
    plant = TetherPlant(cfg)
    peak, worst, ended = 0.0, 0.0, 'ok'
    try:
        for k in range(int(round(duration / CALL)) + 1):
            out = plant.step(k * CALL, inputs_at(k * CALL))
            peak = max(peak, out.tension_uav)
            bal = plant.energy_balance()
            if bal is not None and bal['throughput'] > 0.0:
                worst = max(worst, abs(bal['residual']) / bal['throughput'])
    except PlantDivergenceError as error:
        ended = str(error)
    return {'peak_uav_N': peak, 'residual_share': worst, 'ended': ended}
