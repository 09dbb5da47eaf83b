"""Moving-reel methods compared on one payout profile (issue 10; thesis Sec. 10.4).

Scene: a 1 kg body hanging from a fixed guide way on a stiff tether (mu 0.042 kg/m,
EA 20 kN), paid out from 5 m to 25 m at 2 m/s, held, reeled back in to 5 m at 2 m/s and
held (half-cosine speed ramps of 2 s), prescribed spool rate, Kelvin-Voigt c = 1 N s.
Methods (``PlantConfig.reshape``): 'ale' (this project's), 'last_element' (MoorDyn-F's
DeltaL), 'uniform' (MoorDyn-C / KiteModels: every element L / N each step), 'insert'
(OrcaFlex-style line feeding: whole elements inserted / removed at the reel end, the
undeployed remainder massless). All with 1 m elements at the start (N = 5 for 'uniform'),
the same step, the same plant, in the same run.

Measured: the largest one-step change of the reel tension at dt and dt / 2 (a change that
does not halve with the step is a step the method put there), the RMS error of the reel
tension against the hanging weight (m + mu L) g while paying out and reeling in at
constant speed, the relative mass-conservation error, the energy-balance residual over
the throughput, the largest element-size ratio, and the wall time (kernels compiled
before timing). Writes table.csv, tension.png and summary.txt.

Run:  ./tethersim-env python bench/reel_payout/run.py [--quick] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_dynamics.plant import PlantConfig, PlantInputs, ReelConfig, TetherPlant, UavConfig  # noqa: E402
from tether_models.constants import GRAVITY  # noqa: E402

MU, EA, MASS, L0, TOTAL = 0.042, 2.0e4, 1.0, 5.0, 150.0
G = GRAVITY
METHODS = ('ale', 'last_element', 'uniform', 'insert')
CALL = 0.01


def _ramp(t: float, start: float, duration: float = 2.0) -> float:
    u = min(max((t - start) / duration, 0.0), 1.0)
    return 0.5 - 0.5 * math.cos(math.pi * u)


def profile(t: float, hold: float) -> float:
    """Spool rate (rad/s; 0.1 m radius): out 0.5-10.5 s, in from 10.5 + hold, 20 m each way."""
    back = 10.5 + hold
    return 20.0 * (_ramp(t, 0.5) - _ramp(t, 10.5) - _ramp(t, back) + _ramp(t, back + 10.0))


def run(method: str, dt: float, hold: float) -> dict:
    """One run of the profile; returns the measured row and the time series."""
    cfg = PlantConfig(fidelity='linear', elements=5, element_length=1.0, dt=dt, initial_length=L0,
                      guide_way_offset=(0.0, 0.0, 0.0), mass_per_length=MU, ea=EA, effects=('damping',),
                      damping=1.0, reshape=method,
                      reel=ReelConfig(input='spool_rate', spool_radius=0.1, max_length=60.0, total_length=TOTAL),
                      uav=UavConfig(mode='dynamic', mass=MASS, attach_offset=(0.0, 0.0, 0.0)))
    plant = TetherPlant(cfg)
    end = -L0 * (1.0 + (MASS + MU * L0 / 2.0) * G / EA)
    plant.step(0.0, PlantInputs(uav_position=np.array([0.0, 0.0, end])))
    span = 10.5 + hold + 10.0 + 2.5 + 2.0
    n = int(round(span / CALL))
    series = np.zeros((n, 5))
    ratio = 1.0
    start = time.perf_counter()
    for k in range(1, n + 1):
        t = k * CALL
        out = plant.step(t, PlantInputs(spool_rate=profile(t, hold)))
        rest = np.diff(out.arc_length)
        ratio = max(ratio, float(np.max(rest) / np.min(rest)))
        series[k - 1] = (t, out.tension_reel, out.deployed_length, out.payout_rate, out.uav_acceleration[2])
    wall = time.perf_counter() - start
    fem = plant._fem
    bal = fem.balance()
    t, tension, length, payout, _ = series.T
    weight = (MASS + MU * length) * G
    steady = (np.abs(np.abs(payout) - 2.0) < 1e-9) & (t > 3.0)
    mass_err = abs(plant.total_tether_mass() - MU * TOTAL) / (MU * TOTAL)
    return {'method': method, 'dt': dt, 'wall_s': wall, 'jump_N': fem.largest_reel_tension_step(),
            'rms_err_N': float(np.sqrt(np.mean((tension[steady] - weight[steady]) ** 2))),
            'mass_err': mass_err, 'energy_residual': abs(bal['residual']) / bal['throughput'],
            'size_ratio': ratio, 'events': sum(fem.mesh_events()), 'series': series,
            'jump_t': fem.largest_reel_tension_step_time()}


def _fmt(row: dict) -> str:
    return (f"{row['method']:13s} {row['jump_N']:9.3g} {row['jump_half_N']:9.3g} {row['rms_err_N']:9.3g} "
            f"{row['mass_err']:9.2g} {row['energy_residual']:9.2g} {row['size_ratio']:7.1f} {row['events']:6d} "
            f"{row['wall_s']:7.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--quick', action='store_true', help='shorter hold')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-reel-payout'))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    hold = 2.0 if args.quick else 5.0
    dt = 1e-4
    for method in METHODS:  # compile / load every kernel before timing
        run(method, dt, 0.0)
    rows = []
    for method in METHODS:
        row = run(method, dt, hold)
        row['jump_half_N'] = run(method, dt / 2, hold)['jump_N']
        rows.append(row)
    header = (f"{'method':13s} {'jump dt':>9s} {'jump dt/2':>9s} {'rms err':>9s} {'mass err':>9s} "
              f"{'E resid':>9s} {'size r':>7s} {'events':>6s} {'wall s':>7s}")
    lines = [f'Reel payout 5 -> 25 -> 5 m at 2 m/s, 1 kg end body, EA {EA:g} N, dt {dt:g} s (and dt/2)',
             header] + [_fmt(r) for r in rows]
    best = {k: ', '.join(r['method'] for r in rows if r[k] == min(q[k] for q in rows))
            for k in ('jump_N', 'mass_err', 'rms_err_N')}
    ale = next(r for r in rows if r['method'] == 'ale')
    cheapest = min(rows, key=lambda r: r['wall_s'])
    lines.append(f"smallest tension step: {best['jump_N']}; smallest mass error: {best['mass_err']}; "
                 f"smallest tension error: {best['rms_err_N']}")
    lines.append(f"ale wall time / cheapest ({cheapest['method']}): {ale['wall_s'] / cheapest['wall_s']:.2f}")
    halves = {r['method']: r['jump_N'] / r['jump_half_N'] for r in rows}
    lines.append('step ratio jump(dt)/jump(dt/2) (2 = the change is physical): '
                 + ', '.join(f'{m} {v:.2f}' for m, v in halves.items()))
    text = '\n'.join(lines)
    print(text)
    (args.out / 'summary.txt').write_text(text + '\n')
    with (args.out / 'table.csv').open('w', newline='') as fh:
        writer = csv.writer(fh)
        keys = ['method', 'dt', 'jump_N', 'jump_half_N', 'rms_err_N', 'mass_err', 'energy_residual', 'size_ratio',
                'events', 'wall_s']
        writer.writerow(keys)
        for r in rows:
            writer.writerow([r[k] for k in keys])
    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for r in reversed(rows):
        t, tension, length, _, _ = r['series'].T
        axes[0].plot(t, tension - (MASS + MU * length) * G, lw=0.8, label=r['method'],
                     alpha=0.35 if r['method'] == 'insert' else 1.0)
        axes[1].plot(t, length, lw=0.8, label=r['method'])
    axes[0].set_ylabel('reel tension - (m + mu L) g, N')
    axes[0].set_ylim(-5, 5)
    axes[1].set_ylabel('deployed length, m')
    axes[1].set_xlabel('t, s')
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(args.out / 'tension.png', dpi=120)
    print(f'wrote {args.out}/summary.txt, table.csv, tension.png')


if __name__ == '__main__':
    main()
