"""``tethersim psr``: workspace, design optimization and path tracking of the 3-PSR replicator.

Subcommands:
    optimize   the design parameter study of Sec. 2.5 (Tables 2.2, 2.3, Fig. 2.4)
    workspace  one design's roll-pitch workspace (Fig. 2.3)
    track      a wave or boat profile through the table interpolation (Sec. 2.6-2.7)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from tether_common.command_line import Command
from tether_common.command_line import OneLineParser
from tether_common.command_line import UsageError
from tether_common.command_line import analysis

PROG = 'tethersim psr'


def _progress_printer(label: str):
    last = [0.0]

    def report(done: int, total: int, elapsed: float) -> None:
        if elapsed - last[0] < 5.0 and done != total:
            return
        last[0] = elapsed
        eta = elapsed / done * (total - done)
        print(f'[{PROG} {label}] {done}/{total} designs, {elapsed:.0f} s elapsed, '
              f'ETA {eta / 60:.1f} min', file=sys.stderr, flush=True)

    return report


def _region_ranges(table, region) -> str:
    roll = np.degrees(table.roll[region.points])
    pitch = np.degrees(table.pitch[region.points])
    yaw = np.degrees(table.yaw[region.points])
    return (f'roll {roll.min():+.1f}..{roll.max():+.1f} deg, pitch {pitch.min():+.1f}..{pitch.max():+.1f} deg, '
            f'|yaw| <= {np.abs(yaw).max():.1f} deg')


def cmd_optimize(args: argparse.Namespace) -> list[str]:
    """Run the design study (Sec. 2.5) and compare with Tables 2.2 and 2.3."""
    from psr_platform_sim import optimize
    from psr_platform_sim.kinematics import Design
    from psr_platform_sim.plots import optimized_figure
    from psr_platform_sim.plots import study_figure
    from psr_platform_sim.plots import workspace_figure
    from psr_platform_sim.workspace import ball_region
    from psr_platform_sim.workspace import cached_table
    from psr_platform_sim.workspace import nominal_region

    settings = optimize.QUICK if args.quick else optimize.StudySettings()
    if not 0.0 < args.fraction <= 1.0:
        raise UsageError(f'--fraction must be in (0, 1], got {args.fraction}')
    ratios = settings.ratios
    arm = ratios
    if args.fraction < 1.0:
        count = max(1, int(round(args.fraction * ratios.size)))
        arm = ratios[np.linspace(0, ratios.size - 1, count).round().astype(int)]
    mode = 'quick' if args.quick else 'full'
    print(f'[{PROG} optimize] {mode} study: {ratios.size} x {ratios.size} designs '
          f'({arm.size} arm lengths run), {settings.slider_steps}^2 slider grid, '
          f'{settings.gammas_deg.size} ball-joint angles', file=sys.stderr, flush=True)
    result = optimize.run_study(settings, _progress_printer('optimize'), arm)
    result.save(args.out / 'study.npz')
    designs_run = arm.size * ratios.size
    solves_run = designs_run * settings.slider_steps**2
    full_seconds = result.seconds * ratios.size / arm.size

    lines = [f'3-PSR design study ({mode}; Sec. 2.5): l, d = {ratios[0]:g}..{ratios[-1]:g} r '
             f'in {settings.ratio_step * 100:g} % steps, slider grid {settings.slider_steps}^2, '
             f'gamma {settings.gammas_deg[0]:g}..{settings.gammas_deg[-1]:g} deg',
             f'Newton solves run: {solves_run:,} in {result.seconds:.1f} s '
             f'({result.seconds / solves_run * 1e6:.2f} us per solve incl. post-processing); '
             f'full study {settings.solves:,} solves; thesis (Sec. 2.5): "~70 million numerical solves", '
             f'on a supercomputer with the 41 arm lengths in parallel']
    if arm.size < ratios.size:
        lines.append(f'fraction run: {arm.size}/{ratios.size} arm lengths; extrapolated full study: '
                     f'{settings.solves:,} solves, {full_seconds / 60:.1f} min on this machine')
    lines.append('')
    lines.append('Table 2.2 (no ball-joint limit): project | thesis')
    lines.append(' rank   area deg2    l      d   |  area deg2    l      d')
    top = result.top_nominal()
    for rank, (mine, theirs) in enumerate(zip(top, optimize.TABLE_2_2), start=1):
        lines.append(f'  {rank}    {mine[0]:8.1f}  {mine[1]:5.3f}  {mine[2]:5.3f} |  {theirs[0]:8.1f}  '
                     f'{theirs[1]:5.3f}  {theirs[2]:5.3f}')
    lines.append('')
    lines.append('Table 2.3 (ball-joint limit 30 deg): project | thesis')
    lines.append(' rank   area deg2    l      d    gamma |  area deg2    l      d    gamma')
    top_ball = result.top_ball()
    for rank, (mine, theirs) in enumerate(zip(top_ball, optimize.TABLE_2_3), start=1):
        lines.append(f'  {rank}    {mine[0]:8.1f}  {mine[1]:5.3f}  {mine[2]:5.3f}  {mine[3]:4.0f} |  '
                     f'{theirs[0]:8.1f}  {theirs[1]:5.3f}  {theirs[2]:5.3f}  {theirs[3]:4.0f}')

    lines.append('')
    cache = args.cache
    best = Design(1.0, top[0][1], top[0][2])
    best_ball = Design(1.0, top_ball[0][1], top_ball[0][2], np.radians(top_ball[0][3]))
    thesis_best = Design(1.0, *optimize.TABLE_2_2[0][1:3])
    thesis_ball = Design(1.0, *optimize.TABLE_2_3[0][1:3], np.radians(optimize.TABLE_2_3[0][3]))
    figures = []
    for label, design, limited in (('project best', best, False), ('project best, ball limit', best_ball, True),
                                   ('thesis Table 2.2 #1', thesis_best, False),
                                   ('thesis Table 2.3 #1', thesis_ball, True)):
        table = cached_table(design, settings.slider_steps, cache)
        region = ball_region(table) if limited else nominal_region(table)
        gamma = f', gamma={np.degrees(design.gamma):.0f}' if limited else ''
        lines.append(f'{label} (l={design.l:g}, d={design.d:g}{gamma}): area {region.area:.1f} deg2; '
                     f'{_region_ranges(table, region)}')
        figures.append((table, region, f'{label} l={design.l:g} d={design.d:g}{gamma}'))
    lines.append('thesis (Sec. 2.5, Fig. 2.4): "The roll and pitch range achievable is from -32° to 32° and '
                 '-25° to 35°"')
    study_figure(result, args.out / 'study_area.png')
    optimized_figure([figures[0], figures[1]], args.out / 'optimized_workspace.png')
    workspace_figure(figures[0][0], figures[0][1], args.out / 'workspace_best.png',
                     f'Workspace of the best design, l={best.l:g} r, d={best.d:g} r')
    return lines


def cmd_workspace(args: argparse.Namespace) -> list[str]:
    """Plot one design's workspace (Fig. 2.3) from the cached lookup table."""
    from psr_platform_sim.kinematics import Design
    from psr_platform_sim.plots import workspace_figure
    from psr_platform_sim.workspace import ball_region
    from psr_platform_sim.workspace import cached_table
    from psr_platform_sim.workspace import nominal_region

    for name in ('r', 'l', 'd'):
        if getattr(args, name) <= 0:
            raise UsageError(f'--{name} must be positive, got {getattr(args, name)}')
    if args.steps < 10:
        raise UsageError(f'--steps must be at least 10, got {args.steps}')
    design = Design(args.r, args.l, args.d, np.radians(args.gamma))
    start = time.perf_counter()
    table = cached_table(design, args.steps, args.cache)
    seconds = time.perf_counter() - start
    nominal = nominal_region(table)
    ball = ball_region(table)
    workspace_figure(table, nominal, args.out / 'workspace.png',
                     f'r={design.r:g}, l={design.l:g}, d={design.d:g}')
    workspace_figure(table, ball, args.out / 'workspace_ball.png',
                     f'r={design.r:g}, l={design.l:g}, d={design.d:g}, gamma={args.gamma:g} deg, '
                     f'ball limit {np.degrees(design.ball_limit):g} deg')
    return [f'workspace of r={design.r:g} l={design.l:g} d={design.d:g} ({args.steps}^2 grid, '
            f'table in {seconds:.1f} s incl. cache)',
            f'feasible points (Eq. 2.14-2.15): {table.feasible.mean() * 100:.1f} %',
            f'usable (Eq. 2.16, no kinematic lock): {nominal.area:.1f} deg2, {nominal.components} piece(s); '
            f'{_region_ranges(table, nominal)}',
            f'with ball-joint limit, gamma={args.gamma:g} deg: {ball.area:.1f} deg2; {_region_ranges(table, ball)}']


HPR_THESIS = {'hpr1': (18.1, 16.1), 'hpr2': (14.5, 21.8), 'hpr3': (17.4, 21.1)}
"""Sec. 5.6: pitch and roll amplitude (deg) of the thesis's HPR profiles #1-#3."""


def cmd_track(args: argparse.Namespace) -> list[str]:
    """Wave and boat profiles through Eq. 2.17 and the exact kinematics (Sec. 2.6, 2.7, 5.6)."""
    from psr_platform_sim.kinematics import platform_pose
    from psr_platform_sim.kinematics import solve_corners
    from psr_platform_sim.path import PathGenerator
    from psr_platform_sim.platform_params import PARAMETERS
    from psr_platform_sim.platform_params import from_params
    from psr_platform_sim.plots import profiles_figure
    from psr_platform_sim.plots import tracking_figure
    from psr_platform_sim.simulator import PlatformSimulator
    from psr_platform_sim.validation import workspace_profile
    from psr_platform_sim.workspace import ball_region
    from psr_platform_sim.workspace import cached_table
    from tether_models.waves import ProfileError
    from tether_models.waves import named_profile

    if args.steps < 50:
        raise UsageError(f'--steps must be at least 50, got {args.steps}')
    if args.duration <= 0:
        raise UsageError(f'--duration must be positive, got {args.duration}')
    names = args.profile or ['workspace', 'jonswap', 'hpr1', 'hpr2', 'hpr3']
    params = {spec.name: spec.default for spec in PARAMETERS}
    params.update(table_steps=args.steps, cache_dir=str(args.cache or ''), profile_duration=args.duration,
                  seed=args.seed)
    start = time.perf_counter()
    sim0 = PlatformSimulator(from_params({**params, 'profile': 'still'}))
    table = cached_table(sim0.design, args.steps, args.cache)
    generator = PathGenerator(table, ball_region(table), sim0.rail_base)
    print(f'[{PROG} track] table {args.steps}^2 ready in {time.perf_counter() - start:.1f} s',
          file=sys.stderr, flush=True)
    rate = params['command_rate']
    lines = [f'prototype r={sim0.design.r:g} m, l={sim0.design.l:g} m, d={sim0.design.d:g} m, '
             f'gamma={np.degrees(sim0.design.gamma):g} deg, table {args.steps}^2 (slider step '
             f'{generator.step * 1000:.2f} mm); slider commands at {rate:g} Hz',
             'profile      heave range  |roll| max  |pitch| max  clipped  Eq.2.17 error mean/max (deg)  '
             'played RMS error roll/pitch (deg), heave (mm)']
    profiles, sims = [], []
    for name in names:
        try:
            sim = PlatformSimulator(from_params({**params, 'profile': name}))
            profile = (workspace_profile(table, generator.region) if name == 'workspace'
                       else named_profile(name, args.seed, args.duration, params['sea_state'],
                                          params['boat_length'], rate))
        except ProfileError as error:
            raise UsageError(str(error)) from None
        path = generator.sliders(profile.heave, profile.roll, profile.pitch, exact=False,
                                 heave_limit=params['heave_limit'])
        inside = path.inside
        pose = platform_pose(solve_corners(sim0.design, path.heights + sim0.rail_base)[0])
        error = np.degrees(np.hypot(pose.roll - path.roll, pose.pitch - path.pitch))[inside]
        rms = sim.tracking_error()
        thesis = HPR_THESIS.get(name)
        lines.append(
            f'{name:<12} {np.ptp(profile.heave):6.2f} m   {np.degrees(np.abs(profile.roll).max()):7.1f}    '
            f'{np.degrees(np.abs(profile.pitch).max()):7.1f}    {(1 - sim.inside.mean()) * 100:5.1f} %   '
            f'{error.mean() if error.size else 0.0:.4f} / {error.max() if error.size else 0.0:.4f}'
            f'                 {np.degrees(rms["roll"]):.3f} / {np.degrees(rms["pitch"]):.3f}, '
            f'{rms["heave"] * 1000:.1f}'
            + (f'   (thesis Sec. 5.6: pitch +-{thesis[0]}, roll +-{thesis[1]})' if thesis else ''))
        profiles.append(profile)
        sims.append(sim)
        print(f'[{PROG} track] {name} done', file=sys.stderr, flush=True)
    lines.append('thesis (Sec. 5.6): the heave-only JONSWAP profile "had a 1.6 m peak wave amplitude and a 10 '
                 'second peak period"; the HPR profiles had "a heave range up to ... 2.2 m"')
    lines.append('thesis (Sec. 2.7): the prototype\'s "average error for roll and pitch was 1.2° with a standard '
                 'deviation of 2.8°" (workspace profile) and 3.1° (boat profile)')
    profiles_figure(profiles, args.out / 'profiles.png')
    tracking_figure(sims[-1], args.out / 'tracking.png')
    return lines


def _arguments(parser: argparse.ArgumentParser) -> None:
    """Add the subcommands of ``tethersim psr`` to its parser."""
    sub = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)

    opt = sub.add_parser('optimize', help='design parameter study (Sec. 2.5)')
    opt.add_argument('--quick', action='store_true', help='coarse study: 5 %% steps, 100^2 slider grid')
    opt.add_argument('--fraction', type=float, default=1.0,
                     help='run this fraction of the arm lengths and extrapolate the time')
    opt.add_argument('--cache', type=Path, default=None, help='lookup-table cache directory')
    opt.add_argument('--out', type=Path, default=Path('runs/psr-optimize'))
    opt.set_defaults(func=cmd_optimize)

    ws = sub.add_parser('workspace', help='roll-pitch workspace of one design (Fig. 2.3)')
    ws.add_argument('--r', type=float, default=1.0, help='tower radius')
    ws.add_argument('--l', type=float, default=1.0, help='arm length')
    ws.add_argument('--d', type=float, default=1.0, help='platform edge')
    ws.add_argument('--gamma', type=float, default=30.0, help='ball-joint mounting angle (deg)')
    ws.add_argument('--steps', type=int, default=200, help='slider grid steps per axis')
    ws.add_argument('--cache', type=Path, default=None, help='lookup-table cache directory')
    ws.add_argument('--out', type=Path, default=Path('runs/psr-workspace'))
    ws.set_defaults(func=cmd_workspace)

    tr = sub.add_parser('track', help='wave and boat profiles through the table interpolation (Sec. 2.6-2.7)')
    tr.add_argument('--profile', action='append',
                    help='jonswap, boat, hpr1, hpr2, hpr3, still, workspace or a CSV file (repeatable); '
                         'default: workspace jonswap hpr1 hpr2 hpr3')
    tr.add_argument('--seed', type=int, default=1, help='seed of the jonswap and boat profiles')
    tr.add_argument('--duration', type=float, default=240.0, help='profile length (s)')
    tr.add_argument('--steps', type=int, default=1000, help='lookup-table steps per slider axis (~1000 in Sec. 2.6)')
    tr.add_argument('--cache', type=Path, default=None, help='lookup-table cache directory')
    tr.add_argument('--out', type=Path, default=Path('runs/psr-track'))
    tr.set_defaults(func=cmd_track)


COMMAND = Command('3-PSR wave replicator: workspace, design optimization, path tracking (thesis Ch. 2)',
                  _arguments, analysis(PROG, lambda args: '\n'.join(args.func(args))))
