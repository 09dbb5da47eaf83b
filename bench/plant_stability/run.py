"""How close to the stable-step estimate the moving-reel FEM plant stays stable (issue 36).

A hard case of the held-out class (a stiff, light tether on a moving reel): 30 m of tether,
EA 30 kN, mu 0.015 kg/m, between a guide way heaving +-1 m with a 3 s period and a prescribed
UAV end that is driven 4 m sideways in 0.8 s, while the reel pays out and reels in at 1.5 m/s.
For linear (N = 10, 40) and quadratic (N = 20, 40) elements, without and with internal damping
(Kelvin-Voigt c = 1 N s), the step is scanned from 0.3 to 0.9 of the estimate
:func:`tether_dynamics.plant.fem_reel.stable_step` (the plant itself accepts 0.5 of it
undamped, 0.9 damped: :func:`~tether_dynamics.plant.fem_reel.accepted_step`; the bench lifts
that limit to measure past it); each run reports the peak tension at the UAV end, the largest
energy-balance residual as a share of the throughput so far (in the first 0.5 s, when next to
nothing has flowed, over mu g L^2 instead), and whether the plant's energy watchdog stopped
it (:class:`PlantDivergenceError`).

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
from tether_dynamics.plant import fem_reel, watchdog
from tether_dynamics.plant.fem_reel import PlantDivergenceError, stable_step

LENGTH, EA, MU, RADIUS = 40.0, 4.0e4, 0.01, 0.05
UAV = np.array([28.0, 0.0, 28.0])
CALL = 0.01
DURATION = 6.0
CASES = (('linear', 10, 0.0), ('linear', 10, 1.0), ('linear', 40, 0.0), ('linear', 40, 1.0),
         ('quadratic', 20, 0.0), ('quadratic', 20, 1.0), ('quadratic', 40, 0.0), ('quadratic', 40, 1.0))
FRACTIONS = (0.3, 0.5, 0.7, 0.9)


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
    """Peak UAV-end tension (N), the largest |residual| / throughput of the energy balance after the
    first 0.5 s, the largest |residual| / (mu g L^2) in them, and how the run ended ('ok' or the
    watchdog's message).
    """
    plant = TetherPlant(cfg)
    scale = cfg.mass_per_length * cfg.gravity * cfg.initial_length**2
    peak, late, early, ended = 0.0, 0.0, 0.0, 'ok'
    try:
        for k in range(int(round(duration / CALL)) + 1):
            out = plant.step(k * CALL, inputs_at(k * CALL))
            peak = max(peak, out.tension_uav)
            bal = plant.energy_balance()
            assert bal is not None
            if k * CALL <= 0.5:
                early = max(early, abs(bal['residual']) / scale)
            elif bal['throughput'] > 0.0:
                late = max(late, abs(bal['residual']) / bal['throughput'])
    except PlantDivergenceError as error:
        ended = str(error)
    return {'peak_uav_N': peak, 'residual_share': late, 'residual_start': early, 'ended': ended}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='linear N = 40 only, undamped and damped')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-plant-stability'))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    fem_reel.UNDAMPED_FRACTION = fem_reel.STABLE_FRACTION = 1.0   # measure past the accepted step
    cases = [c for c in CASES if c[:2] == ('linear', 40)] if args.quick else CASES
    rows = []
    for fidelity, n, damping in cases:
        for fraction in FRACTIONS:
            row = {'fidelity': fidelity, 'N': n, 'damping': damping, 'fraction': fraction,
                   **run(config(fidelity, n, damping, fraction))}
            rows.append(row)
            print(f"{fidelity:9s} N {n:2d} c {damping:3.1f} N s  dt {fraction:.1f} x estimate  "
                  f"peak UAV tension {row['peak_uav_N']:9.1f} N  residual {row['residual_share']:8.3g} of throughput"
                  f"  start {row['residual_start']:8.2e} mu g L^2  {row['ended']}", flush=True)
    healthy = [r for r in rows if r['ended'] == 'ok']
    lines = [f'Hard case: {LENGTH:g} m, EA {EA:g} N, mu {MU:g} kg/m, reel heaving +-1.5 m, paying out and in at '
             '2.5 m/s, far end 4 m sideways in 0.6 s',
             *(f"{r['fidelity']:9s} N {r['N']:2d} c {r['damping']:3.1f} dt {r['fraction']:.1f} x estimate: peak "
               f"{r['peak_uav_N']:9.1f} N, residual {r['residual_share']:.3g} of throughput, "
               f"{r['residual_start']:.2e} mu g L^2 at the start, {r['ended']}" for r in rows),
             f"runs the watchdog let finish: residual at most {max(r['residual_share'] for r in healthy):.3g} of the "
             f"throughput, {max(r['residual_start'] for r in healthy):.2e} mu g L^2 at the start "
             f"(watchdog: {watchdog.SHARE:g} of the throughput + {watchdog.FLOOR:g} mu g L^2)"]
    text = '\n'.join(lines)
    print(text)
    (args.out / 'summary.txt').write_text(text + '\n')
    with (args.out / 'scan.csv').open('w', newline='') as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f'wrote {args.out}/summary.txt, scan.csv')


if __name__ == '__main__':
    main()
