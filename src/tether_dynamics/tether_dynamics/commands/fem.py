"""Command line of the FEM tether model: ``tethersim fem pendulum`` (thesis Chapter 9)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from tether_common.command_line import Command
from tether_common.command_line import OneLineParser
from tether_common.command_line import UsageError
from tether_common.command_line import analysis
from tether_common.command_line import positive
from tether_dynamics.fem.errors import FemError

PROG = 'tethersim fem'


def _arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='command', required=True, parser_class=OneLineParser)
    pend = sub.add_parser('pendulum', help='reproduce the Chapter 9 pendulum (Fig. 9.1-9.4)')
    pend.add_argument('--elements', default='linear,quadratic',
                      help="comma list of 'linear', 'quadratic' (default both)")
    pend.add_argument('--n', type=positive(int), default=5, help='number of elements (default 5)')
    pend.add_argument('--dt', type=positive(float), default=1e-4, help='time step, s (default 1e-4)')
    pend.add_argument('--span', type=positive(float), default=10.0, help='simulated time, s (default 10)')
    pend.add_argument('--method', choices=('rk4', 'verlet'), default='rk4')
    pend.add_argument('--body', choices=('rigid', 'point'), default='rigid')
    pend.add_argument('--out', type=Path, default=Path('runs/fem-pendulum'))


def _pendulum(args: argparse.Namespace) -> str:
    from tether_dynamics.commands import pendulum  # noqa: PLC0415 - keeps --help fast
    from tether_dynamics.fem.integrators import warm_up  # noqa: PLC0415

    elements = [e.strip() for e in args.elements.split(',') if e.strip()]
    bad = [e for e in elements if e not in ('linear', 'quadratic')]
    if bad or not elements:
        raise UsageError(f"--elements takes 'linear' and/or 'quadratic', got {args.elements!r}")
    print(f'{PROG} pendulum: loading compiled kernels (compiling on first use, ~20-60 s)...', file=sys.stderr)
    jit = warm_up()
    runs = []
    for element in elements:
        print(f'{PROG} pendulum: {element} elements, N={args.n}, dt={args.dt:g} s, {args.span:g} s...',
              file=sys.stderr)
        res = pendulum.run(element, args.n, args.dt, args.span, args.method, args.body)
        pendulum.plot_snapshots(res, args.out / f'snapshots_{element}.png')
        runs.append(res)
    pendulum.plot_energy(runs, args.out / 'energy.png')
    pendulum.plot_length(runs, args.out / 'length.png')
    print(f'{PROG} pendulum: sensitivity check (same run at dt/2)...', file=sys.stderr)
    lines = [f'Chapter 9 pendulum: N = {args.n}, {args.method} dt = {args.dt:g} s, {args.span:g} s, '
             f'{args.body} body, tension-only string',
             f'kernel start-up (load from cache or compile) {jit:.2f} s, not counted in wall times below']
    sensitivity = {}
    for res in runs:
        lines += pendulum.summary_lines(res, args.span)
        lines.append(pendulum.stable_step_line(res.element, args.n, args.dt))
        half = pendulum.run(res.element, args.n, args.dt / 2, args.span, args.method, args.body)
        lines.append('  ' + pendulum.sensitivity_line(res, half))
        sensitivity[res.element] = pendulum.end_distance(res, half, args.span)
    print(f'{PROG} pendulum: control run with a string that also resists compression...', file=sys.stderr)
    control = pendulum.run(elements[0], args.n, args.dt, args.span, args.method, args.body, tension_only=False)
    half = pendulum.run(elements[0], args.n, args.dt / 2, args.span, args.method, args.body, tension_only=False)
    sensitivity[f'{elements[0]} resisting compression'] = pendulum.end_distance(control, half, args.span)
    lines += pendulum.verdict(runs, control, sensitivity)
    return '\n'.join(lines) + '\n'


COMMAND = Command('finite-element tether dynamics (thesis Ch. 7-9), the Chapter 9 pendulum', _arguments,
                  analysis(PROG, _pendulum, user_errors=(FemError,)))
