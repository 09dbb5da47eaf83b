"""Accuracy / wall-time trade-off of the FEM tether against MoorDyn and the thesis's MATLAB.

Reference scene: the Chapter 9 pendulum with a point mass (the scene MoorDyn can model),
10 s simulated. For every element type x N x integrator x step it measures the wall time
(best of repeats, JIT excluded), the energy error max|E - E0| / peak KE sampled every
10 ms, and the end-mass error against (a) the same model at a 20x smaller RK4 step
(time-stepping error) and (b) quadratic N = 50 at a small step (the converged string),
both over 0-3 s, before slack-taut snaps make the motion chaotic. MoorDyn 2.7.2 runs the
same scene "in air" in the same process, and so does the tether plant every scene runs
(``tether_dynamics.plant``: lumped masses, symplectic Euler, its reel held, its UAV body a
point mass), stepped every 10 ms through its public ``TetherPlant.step`` as the plant node
steps it. Prints a table, the performance-goal verdicts, and writes table.csv, pareto.png
and summary.txt.

Run:  ./tethersim-env python bench/fem_tradeoff/run.py [--quick] [--out DIR]
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_dynamics.fem import diagnostics, scenes  # noqa: E402
from tether_dynamics.fem.errors import DivergenceError  # noqa: E402
from tether_dynamics.fem.integrators import simulate, warm_up  # noqa: E402
from tether_dynamics.fem.model import compile_scene, stable_step  # noqa: E402
from tether_dynamics.plant import PlantInputs, TetherPlant  # noqa: E402
from tether_dynamics.plant.fem_reel import PlantDivergenceError, accepted_step  # noqa: E402
from tether_models.constants import GRAVITY  # noqa: E402

SPAN = 10.0
SAMPLE = 0.01
TRAJ_WINDOW = 3.0
THESIS_RTF = {'linear': SPAN / scenes.THESIS_WALL['linear'], 'quadratic': SPAN / scenes.THESIS_WALL['quadratic']}
MOORDYN_STEPS = (5e-3, 4e-3, 2.5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4)
# MoorDyn's "largest stable step": the largest dtM whose energy error stays below this
# (larger steps finish but drift by percent or blow up; cf. <= 1.6e-3 in the peer notes).
MOORDYN_STABLE_ENERGY = 2e-3
# The plant's steps, as fractions of the step it accepts (symplectic Euler: its energy error is first
# order in the step).
PLANT_FRACTIONS = (1.0, 0.5, 0.25, 0.12)
# Issue 36's goal for the one engine: at least 3x MoorDyn at N = 20 at MoorDyn's energy error.
PLANT_MOORDYN_GOAL = {20: 3.0}
# Equal-accuracy comparison of the element types: end-mass error vs quadratic N = 50.
EQUAL_ACCURACY_M = 6e-3


@dataclass
class Row:
    """One benchmark run."""

    model: str
    n: int
    method: str
    dt: float
    wall: float
    energy_err: float
    traj_err_time: float
    traj_err_ref: float


def grid_dt(target: float) -> float:
    """Largest step <= target that divides the 10 ms sampling interval."""
    return SAMPLE / int(np.ceil(SAMPLE / target - 1e-9))


def energy_error(total: np.ndarray, kinetic: np.ndarray) -> float:
    """max |E - E0| / peak kinetic energy."""
    return float(np.max(np.abs(total - total[0])) / kinetic.max())


def end_error(t_a: np.ndarray, x_a: np.ndarray, t_b: np.ndarray, x_b: np.ndarray) -> float:
    """Largest end-mass distance over the first TRAJ_WINDOW seconds at common 10 ms samples."""
    ka = np.rint(t_a / SAMPLE).astype(int)
    kb = np.rint(t_b / SAMPLE).astype(int)
    common, ia, ib = np.intersect1d(ka, kb, return_indices=True)
    keep = common * SAMPLE <= TRAJ_WINDOW + 1e-9
    return float(np.max(np.linalg.norm(x_a[ia[keep]] - x_b[ib[keep]], axis=1)))


def timed_fem(model, dt: float, method: str, repeats: int):  # noqa: ANN001, ANN201
    """Best-of-repeats wall time and the trajectory of one FEM run."""
    every = int(round(SAMPLE / dt))
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        traj = simulate(model, SPAN, dt, method, record_every=every)
        best = min(best, time.perf_counter() - start)
        if best > 1.0:
            break
    return best, traj


@contextlib.contextmanager
def quiet_stdout():  # noqa: ANN201
    """Silence MoorDyn's per-step 't = ...' prints (written by C code to fd 1)."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, 'w') as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            sys.stdout.flush()
            os.dup2(saved, 1)
            os.close(saved)


MOORDYN_INPUT = """--------------------- MoorDyn Input File ------------------------------------
Chapter 9 pendulum in air (tethersim bench)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI     Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)     (N-m^2) (-)   (-)    (-)     (-)
tether     0.0047  {mu}  {ea}   0           0      0      0      0       0
---------------------------- POINTS ----------------------------------------------
ID   Attachment  X       Y       Z      Mass   Volume  CdA    Ca
(#)   (-)        (m)     (m)     (m)    (kg)   (m^3)   (m^2)  (-)
1    Fixed       0       0       0      0      0       0      0
2    Free        {x}  {y}  {z}  {mass}  0       0      0
---------------------------- LINES -----------------------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)      (-)
1    tether     1        2        {length}     {n}      -
---------------------------- OPTIONS -----------------------------------------------------
{dt}     dtM
1000     WtrDpth
0        WtrDnsty
{g}     g
0        TmaxIC
{scheme}  tScheme
---------------------------- OUTPUTS -----------------------------------------------------
END
------------------------- need this line -------------------------------------------------
"""


def moordyn_run(n: int, dt: float, workdir: Path, scheme: str = 'RK4', span: float = SPAN):  # noqa: ANN201
    """MoorDyn on the same scene in air; returns (wall, t, end positions, total E, kinetic E) or None if it blew up."""
    import moordyn  # noqa: PLC0415 - optional peer

    x, y, z = scenes.PENDULUM_RELEASE
    path = workdir / f'md_{n}_{dt:g}_{scheme}.txt'
    path.write_text(MOORDYN_INPUT.format(g=GRAVITY, mu=scenes.PENDULUM_MU, ea=scenes.PENDULUM_EA, x=x, y=y, z=z,
                                         mass=scenes.PENDULUM_MASS, length=scenes.PENDULUM_LENGTH, n=n,
                                         dt=dt, scheme=scheme))
    l0 = scenes.PENDULUM_LENGTH / n
    masses = np.full(n + 1, scenes.PENDULUM_MU * l0)
    masses[[0, -1]] *= 0.5
    masses[-1] += scenes.PENDULUM_MASS
    n_out = int(round(span / SAMPLE))
    pos = np.empty((n_out + 1, n + 1, 3))
    vel = np.empty_like(pos)
    with quiet_stdout():
        system = moordyn.Create(str(path))
        moordyn.Init_NoIC(system, [], [])
        line = moordyn.GetLine(system, 1)

        def sample(k: int) -> None:
            for i in range(n + 1):
                pos[k, i] = moordyn.GetLineNodePos(line, i)
                vel[k, i] = moordyn.GetLineNodeVel(line, i)
        sample(0)
        wall = 0.0
        ok = True
        try:
            for k in range(n_out):
                start = time.perf_counter()
                moordyn.Step(system, [], [], k * SAMPLE, SAMPLE)
                wall += time.perf_counter() - start
                sample(k + 1)
                if not np.all(np.isfinite(pos[k + 1])) or np.max(np.abs(pos[k + 1])) > 100.0:
                    ok = False
                    break
        except (RuntimeError, ValueError):
            ok = False
        moordyn.Close(system)
    if not ok:
        return None
    t = SAMPLE * np.arange(n_out + 1)
    kinetic = 0.5 * np.einsum('i,ric->r', masses, vel**2)
    seg = np.linalg.norm(np.diff(pos, axis=1), axis=2)
    eps = np.maximum(seg / l0 - 1.0, 0.0)
    elastic = 0.5 * scenes.PENDULUM_EA * l0 * np.sum(eps**2, axis=1)
    gravity = GRAVITY * np.einsum('i,ri->r', masses, pos[:, :, 2])
    return wall, t, pos[:, -1], kinetic + gravity + elastic, kinetic


def plant_run(element: str, n: int, dt: float, span: float = SPAN, stepper: str = 'held', repeats: int = 1):  # noqa: ANN201
    """The plant on the pendulum; returns (wall, t, end positions, total E, kinetic E), energies from the
    plant's own accounts (tether kinetic, gravity and strain, plus the end body's), or None if it diverged.
    ``stepper`` 'held': the whole run in one call (``TetherPlant.run_held``); 'call': ``TetherPlant.step``
    at every sample, as the plant node steps it (the same samples, bit for bit). Wall: best of ``repeats``.
    """
    release = PlantInputs(uav_position=np.array(scenes.PENDULUM_RELEASE))
    t = SAMPLE * np.arange(int(round(span / SAMPLE)) + 1)
    walls = []
    for _ in range(repeats):
        plant = TetherPlant(scenes.pendulum_plant(element, n, dt))
        start = time.perf_counter()
        try:
            if stepper == 'held':
                run = plant.run_held(t, release)
            else:
                outs = [plant.step(float(tk), release) for tk in t]
        except PlantDivergenceError:
            return None
        walls.append(time.perf_counter() - start)
    if stepper == 'held':
        end, velocity = run.uav_position, run.uav_velocity
        tether_kinetic, tether_rest = run.kinetic_energy, run.potential_energy + run.strain_energy
    else:
        end, velocity = np.array([o.uav_position for o in outs]), np.array([o.uav_velocity for o in outs])
        tether_kinetic = np.array([o.kinetic_energy for o in outs])
        tether_rest = np.array([o.potential_energy + o.strain_energy for o in outs])
    kinetic = tether_kinetic + 0.5 * scenes.PENDULUM_MASS * np.einsum('ij,ij->i', velocity, velocity)
    total = kinetic + tether_rest + scenes.PENDULUM_MASS * GRAVITY * end[:, 2]
    return min(walls), t, end, total, kinetic


def jit_costs() -> tuple[float, float]:
    """Cold compile and cached load of every kernel, each in a fresh process with its own cache."""
    code = 'from tether_dynamics.fem.integrators import warm_up; print(warm_up())'
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        runs = [float(subprocess.run([sys.executable, '-c', code], env=env, check=True, capture_output=True,
                                     text=True).stdout.split()[-1]) for _ in range(2)]
    return runs[0], runs[1]


def pareto_plot(rows: list[Row], path: Path) -> None:
    """Energy error and end-mass error against wall time, one marker per run."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    styles = {'linear': 'o', 'quadratic': 's', 'moordyn': '^', 'plant-linear': 'D', 'plant-quadratic': 'P'}
    colors = {5: 'tab:blue', 10: 'tab:orange', 20: 'tab:green', 50: 'tab:red'}
    for r in rows:
        mk = styles[r.model]
        face = colors[r.n] if r.method != 'verlet' else 'none'
        for ax, val in zip(axes, (r.energy_err, r.traj_err_ref)):
            ax.loglog(r.wall, max(val, 1e-12), mk, color=colors[r.n], markerfacecolor=face, ms=7)
    labels = ('energy error max|E-E0| / peak KE', f'end-mass error vs quadratic N=50, 0-{TRAJ_WINDOW:g} s [m]')
    for ax, label in zip(axes, labels):
        ax.set_xlabel('wall time for 10 s simulated [s]')
        ax.set_ylabel(label)
        ax.grid(True, which='both', alpha=0.3)
    handles = [plt.Line2D([], [], marker=m, ls='', color='k', label=k) for k, m in styles.items()]
    handles += [plt.Line2D([], [], marker='o', ls='', color=c, label=f'N={n}') for n, c in colors.items()]
    handles.append(plt.Line2D([], [], marker='o', ls='', color='k', markerfacecolor='none', label='verlet (open)'))
    axes[0].axhline(1.6e-3, color='k', ls=':', lw=0.8)
    axes[0].legend(handles=handles, fontsize=8, loc='lower left')
    fig.suptitle('FEM tether vs MoorDyn on the Chapter 9 pendulum (point mass), 10 s simulated')
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:  # noqa: C901, PLR0912, PLR0915
    """Run the benchmark."""
    parser = argparse.ArgumentParser(prog='bench/fem_tradeoff/run.py')
    parser.add_argument('--quick', action='store_true', help='N in {5, 20}, no cold-compile measurement')
    parser.add_argument('--out', type=Path, default=Path('runs/bench-fem-tradeoff'))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    ns = (5, 20) if args.quick else (5, 10, 20, 50)
    log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731

    if args.quick:
        cold = None
    else:
        log('measuring JIT: cold compile and cached load in fresh processes...')
        cold, cached = jit_costs()
    here = warm_up()
    log('reference: quadratic N=50 at a small RK4 step...')
    ref_model = compile_scene(scenes.pendulum('quadratic', 50, 'point'))
    ref_dt = grid_dt(0.1 * stable_step(ref_model.scene.tether)['dt_rk4'])
    ref = simulate(ref_model, TRAJ_WINDOW + SAMPLE, ref_dt, record_every=int(round(SAMPLE / ref_dt)))
    rows: list[Row] = []
    for element in ('linear', 'quadratic'):
        for n in ns:
            model = compile_scene(scenes.pendulum(element, n, 'point'))
            limits = stable_step(model.scene.tether)
            fine_dt = grid_dt(limits['dt_rk4'] / 20)
            fine = simulate(model, TRAJ_WINDOW + SAMPLE, fine_dt, record_every=int(round(SAMPLE / fine_dt)))
            configs = [('rk4', grid_dt(1e-4))]
            configs += [('rk4', grid_dt(f * limits['dt_rk4'])) for f in (0.9, 0.7, 0.5, 0.35, 0.25)]
            configs += [('verlet', grid_dt(f * limits['dt_verlet'])) for f in (0.9, 0.8, 0.7, 0.6, 0.5, 0.35, 0.25)]
            for method, dt in sorted(set(configs)):
                log(f'{element} N={n} {method} dt={dt:.3g}...')
                try:
                    wall, traj = timed_fem(model, dt, method, repeats=3)
                except DivergenceError as err:
                    log(f'  diverged: {err}')
                    continue
                d = diagnostics.compute(model, traj)
                rows.append(Row(element, n, method, dt, wall, energy_error(d.total, d.kinetic),
                                end_error(traj.t, traj.nodes[:, -1], fine.t, fine.nodes[:, -1]),
                                end_error(traj.t, traj.nodes[:, -1], ref.t, ref.nodes[:, -1])))
    for element in ('linear', 'quadratic'):
        plant_run(element, 5, grid_dt(accepted_step(scenes.pendulum_plant(element, 5, 1e-6))), span=SAMPLE)  # compile
        for n in ns:
            limit = accepted_step(scenes.pendulum_plant(element, n, 1e-6))
            fine_plant = plant_run(element, n, grid_dt(limit / 20), span=TRAJ_WINDOW + SAMPLE)
            for fraction in PLANT_FRACTIONS:
                dt = grid_dt(fraction * limit)
                log(f'plant {element} N={n} dt={dt:.3g}...')
                res = plant_run(element, n, dt, repeats=3)
                if res is None or fine_plant is None:
                    log('  diverged')
                    continue
                wall, t, end, total, kinetic = res
                rows.append(Row(f'plant-{element}', n, 'euler', dt, wall, energy_error(total, kinetic),
                                end_error(t, end, fine_plant[1], fine_plant[2]), end_error(t, end, ref.t, ref.nodes[:, -1])))
    moordyn_largest: dict[int, Row] = {}
    with tempfile.TemporaryDirectory() as work:
        for n in ns:
            fine_md = moordyn_run(n, 2.5e-5, Path(work), span=TRAJ_WINDOW + SAMPLE)
            for dt in MOORDYN_STEPS:
                log(f'moordyn N={n} RK4 dtM={dt:g}...')
                res = moordyn_run(n, dt, Path(work))
                if res is None:
                    log('  blew up')
                    continue
                wall, t, end, total, kinetic = res
                row = Row('moordyn', n, 'rk4', dt, wall, energy_error(total, kinetic),
                          end_error(t, end, fine_md[1], fine_md[2]), end_error(t, end, ref.t, ref.nodes[:, -1]))
                rows.append(row)
                if n not in moordyn_largest and row.energy_err <= MOORDYN_STABLE_ENERGY:
                    moordyn_largest[n] = row
    with open(args.out / 'table.csv', 'w', newline='') as fh:
        writer = csv.writer(fh)
        writer.writerow(['model', 'N', 'method', 'dt_s', 'wall_s', 'rtf', 'energy_err', 'end_err_time_m',
                         'end_err_vs_q50_m'])
        for r in rows:
            writer.writerow([r.model, r.n, r.method, f'{r.dt:.4g}', f'{r.wall:.4g}', f'{SPAN / r.wall:.4g}',
                             f'{r.energy_err:.3g}', f'{r.traj_err_time:.3g}', f'{r.traj_err_ref:.3g}'])
    pareto_plot(rows, args.out / 'pareto.png')

    lines = ['FEM tether trade-off on the Chapter 9 pendulum (point mass), 10 s simulated',
             f'{"model":9} {"N":>3} {"method":6} {"dt [s]":>9} {"wall [s]":>9} {"RTF":>8} {"dE/KEpk":>9} '
             f'{"end err dt":>10} {"end err q50":>11}']
    for r in rows:
        lines.append(f'{r.model:9} {r.n:3d} {r.method:6} {r.dt:9.3g} {r.wall:9.4f} {SPAN / r.wall:8.1f} '
                     f'{r.energy_err:9.2e} {r.traj_err_time:10.2e} {r.traj_err_ref:11.2e}')
    if cold is not None:
        lines.append(f'JIT start-up: cold compile {cold:.1f} s (once per machine, cache=True), '
                     f'load from cache {cached:.2f} s per new process; this process {here:.2f} s')
    lines.append(f'Thesis MATLAB (N=5, RK4 1e-4, 10 s): linear {scenes.THESIS_WALL["linear"]} s (RTF '
                 f'{THESIS_RTF["linear"]:.2f}), quadratic {scenes.THESIS_WALL["quadratic"]} s (RTF '
                 f'{THESIS_RTF["quadratic"]:.2f})')
    lines.append('Performance goals:')
    for n in ns:
        md = moordyn_largest.get(n)
        if md is None:
            lines.append(f'  N={n}: MoorDyn had no stable step in the list')
            continue
        ours = [r for r in rows if r.model in ('linear', 'quadratic') and r.n == n and r.energy_err <= md.energy_err]
        if not ours:
            lines.append(f'  N={n}: no FEM run reached MoorDyn energy error {md.energy_err:.2e}: NOT MET')
            continue
        best = min(ours, key=lambda r: r.wall)
        verdict = 'met' if best.wall <= md.wall else 'NOT MET'
        lines.append(f'  N={n}: MoorDyn largest stable RK4 step {md.dt:g} s: {md.wall:.4f} s, energy error '
                     f'{md.energy_err:.2e}; fastest FEM at <= that error: {best.model} {best.method} dt {best.dt:.3g}: '
                     f'{best.wall:.4f} s -> {md.wall / best.wall:.1f}x MoorDyn ({verdict})')
        plant = [r for r in rows if r.model.startswith('plant-') and r.n == n and r.energy_err <= md.energy_err]
        if plant:
            fastest = min(plant, key=lambda r: r.wall)
            goal = (f' (goal >= {PLANT_MOORDYN_GOAL[n]:g}x: '
                    f'{"met" if md.wall / fastest.wall >= PLANT_MOORDYN_GOAL[n] else "NOT MET"})'
                    if n in PLANT_MOORDYN_GOAL else '')
            per_call = plant_run(fastest.model.removeprefix('plant-'), n, fastest.dt, stepper='call', repeats=3)
            lines.append(f'  N={n}: fastest plant (the scenes\' engine, whole run) at <= that error: {fastest.model} '
                         f'dt {fastest.dt:.3g}: {fastest.wall:.4f} s -> {md.wall / fastest.wall:.1f}x MoorDyn{goal}, '
                         f'{best.wall / fastest.wall:.2f}x the fem engine; stepped per 10 ms call as the plant node '
                         f'steps it: {per_call[0]:.4f} s ({per_call[0] / fastest.wall:.1f}x the whole run)')
        else:
            lines.append(f'  N={n}: no plant run reached MoorDyn energy error {md.energy_err:.2e}')
    threshold = 1.6e-3
    for n in ns:
        best = {}
        for element in ('linear', 'quadratic'):
            ok = [r for r in rows if r.model == element and r.n == n and r.energy_err <= threshold]
            if ok:
                best[element] = min(ok, key=lambda r: r.wall)
        if len(best) == 2:
            ratio = best['quadratic'].wall / best['linear'].wall
            lines.append(f'  N={n}: quadratic / linear cost at energy error <= {threshold:g}: {ratio:.2f} '
                         f'({"met" if ratio <= 2.0 else "NOT MET"}, goal <= 2)')
    best_acc = {}
    for element in ('linear', 'quadratic'):
        ok = [r for r in rows if r.model == element and r.traj_err_ref <= EQUAL_ACCURACY_M
              and r.energy_err <= threshold and not (element == 'quadratic' and r.n == 50)]
        if ok:
            best_acc[element] = min(ok, key=lambda r: r.wall)
    if len(best_acc) == 2:
        lin, quad = best_acc['linear'], best_acc['quadratic']
        lines.append(f'  equal accuracy (end error vs quadratic N=50 <= {EQUAL_ACCURACY_M * 1e3:g} mm and energy '
                     f'error <= {threshold:g}, reference excluded): '
                     f'linear N={lin.n} {lin.method} {lin.wall:.4f} s, quadratic N={quad.n} {quad.method} '
                     f'{quad.wall:.4f} s -> quadratic/linear {quad.wall / lin.wall:.2f}')
    for element in ('linear', 'quadratic'):
        base = [r for r in rows if r.model == element and r.n == 5 and r.method == 'rk4' and abs(r.dt - 1e-4) < 1e-12]
        fast = [r for r in rows if r.model == element and r.n == 5 and r.energy_err <= threshold]
        if base and fast:
            b, f = base[0], min(fast, key=lambda r: r.wall)
            lines.append(f'  {element} N=5: thesis setup (RK4 1e-4) RTF {SPAN / b.wall:.0f} = '
                         f'{SPAN / b.wall / THESIS_RTF[element]:.0f}x thesis; fastest at energy error <= '
                         f'{threshold:g} ({f.method} dt {f.dt:.3g}) RTF {SPAN / f.wall:.0f} = '
                         f'{SPAN / f.wall / THESIS_RTF[element]:.0f}x thesis (goal >= 100x)')
    text = '\n'.join(lines) + '\n'
    (args.out / 'summary.txt').write_text(text)
    print(text, end='')
    return 0


if __name__ == '__main__':
    sys.exit(main())
