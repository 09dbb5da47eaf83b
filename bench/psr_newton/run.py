"""Benchmark: Newton solves of the 3-PSR constraints (Eq. 2.1-2.3) on the thesis's workspace grid.

Compares the project's numba kernel (parallel and one thread) with a batched numpy Newton
and a scipy.optimize.fsolve loop (MATLAB-fsolve-like), after checking they agree.
"""

from __future__ import annotations

import argparse
import sys
import time

import numba
import numpy as np
from scipy.optimize import fsolve

from psr_platform_sim.kinematics import Design
from psr_platform_sim.kinematics import initial_guess
from psr_platform_sim.kinematics import slider_points
from psr_platform_sim.kinematics import solve_corners

DESIGN = Design(1.0, 0.975, 1.15)
FULL_STUDY = 41 * 41 * 200 * 200


def residual_jacobian(s, c, l, d):
    """Eq. 2.1-2.3 (squared lengths) and their Jacobian for stacked configurations."""
    n = c.shape[0]
    f = np.empty((n, 9))
    jac = np.zeros((n, 9, 9))
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        arm = s[:, i] - c[:, i]
        edge = c[:, i] - c[:, j]
        back = c[:, j] - c[:, k]
        f[:, i] = np.sum(arm * arm, axis=1) - l * l
        f[:, 3 + i] = np.sum(edge * edge, axis=1) - d * d
        f[:, 6 + i] = np.sum(arm * back, axis=1)
        jac[:, i, 3 * i:3 * i + 3] = -2.0 * arm
        jac[:, 3 + i, 3 * i:3 * i + 3] = 2.0 * edge
        jac[:, 3 + i, 3 * j:3 * j + 3] = -2.0 * edge
        jac[:, 6 + i, 3 * i:3 * i + 3] -= back
        jac[:, 6 + i, 3 * j:3 * j + 3] += arm
        jac[:, 6 + i, 3 * k:3 * k + 3] -= arm
    return f, jac


def numpy_newton(heights, tol=1e-13, max_iter=40):
    """Batched Newton with np.linalg.solve; singular or diverged systems are frozen."""
    s = slider_points(DESIGN, heights)
    c = initial_guess(DESIGN, heights).reshape(-1, 9)
    active = np.ones(c.shape[0], dtype=bool)
    for _ in range(max_iter):
        f, jac = residual_jacobian(s[active], c[active].reshape(-1, 3, 3), DESIGN.l, DESIGN.d)
        worst = np.abs(f).max(axis=1)
        go = (worst > tol) & np.isfinite(worst) & (worst < 1e6) & (np.abs(np.linalg.det(jac)) > 1e-14)
        index = np.flatnonzero(active)
        active[index[~go]] = False
        if not go.any():
            break
        step = np.linalg.solve(jac[go], -f[go][..., None])[..., 0]
        c[index[go]] += step
    f, _ = residual_jacobian(s, c.reshape(-1, 3, 3), DESIGN.l, DESIGN.d)
    return c.reshape(-1, 3, 3), np.abs(f).max(axis=1) <= tol


def fsolve_loop(heights):
    """scipy.optimize.fsolve per configuration."""
    s = slider_points(DESIGN, heights)
    guess = initial_guess(DESIGN, heights)
    out = np.empty_like(guess)
    ok = np.empty(heights.shape[0], dtype=bool)
    for q in range(heights.shape[0]):
        def fun(x, q=q):
            return residual_jacobian(s[q:q + 1], x.reshape(1, 3, 3), DESIGN.l, DESIGN.d)[0][0]

        def jac(x, q=q):
            return residual_jacobian(s[q:q + 1], x.reshape(1, 3, 3), DESIGN.l, DESIGN.d)[1][0]

        x, _, flag, _ = fsolve(fun, guess[q].ravel(), fprime=jac, full_output=True, xtol=1e-13)
        out[q] = x.reshape(3, 3)
        ok[q] = flag == 1 and np.abs(fun(x)).max() < 1e-10
    return out, ok


def best_of(fn, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeats', type=int, default=3)
    parser.add_argument('--fsolve-subset', type=int, default=400)
    args = parser.parse_args()
    u = np.linspace(-2.5, 2.5, 200)
    heights = np.stack(np.broadcast_arrays(0.0, u[:, None], u[None, :]), axis=-1).reshape(-1, 3)
    n = heights.shape[0]
    solve_corners(DESIGN, heights[:10])  # compile / load the numba cache before timing

    threads = numba.get_num_threads()
    t_par, (c_par, _, ok_par) = best_of(lambda: solve_corners(DESIGN, heights), args.repeats)
    numba.set_num_threads(1)
    t_one, (c_one, _, ok_one) = best_of(lambda: solve_corners(DESIGN, heights), args.repeats)
    numba.set_num_threads(threads)
    t_np, (c_np, ok_np) = best_of(lambda: numpy_newton(heights), args.repeats)
    rng = np.random.default_rng(0)
    subset = rng.choice(n, args.fsolve_subset, replace=False)
    t_fs, (c_fs, ok_fs) = best_of(lambda: fsolve_loop(heights[subset]), 1)
    t_fs_full = t_fs * n / subset.size

    both = ok_par & ok_np
    agree = np.abs(c_par[both] - c_np[both]).max()
    same_set = np.array_equal(ok_par, ok_np) and np.array_equal(ok_par, ok_one)
    both_fs = ok_par[subset] & ok_fs
    agree_fs = np.abs(c_par[subset][both_fs] - c_fs[both_fs]).max()
    print(f'{n} configurations (thesis grid, one design l=0.975 d=1.15); converged: numba {ok_par.sum()}, '
          f'numpy {ok_np.sum()}, fsolve {ok_fs.sum()}/{subset.size}')
    print(f'agreement: numba vs numpy max |dc| = {agree:.1e}, vs fsolve {agree_fs:.1e}, same converged set: {same_set}')
    if agree > 1e-9 or agree_fs > 1e-8:
        print('methods disagree; not timing', file=sys.stderr)
        return 1
    print(f'{"method":<34}{"s / 40k solves":>16}{"us / solve":>12}{"ratio":>9}{"full study (67.2M)":>22}')
    for name, t in ((f'numba kernel, {threads} threads (project)', t_par), ('numba kernel, 1 thread', t_one),
                    ('numpy batched Newton (baseline)', t_np),
                    (f'scipy fsolve loop ({subset.size} run, extrap.)', t_fs_full)):
        print(f'{name:<34}{t:16.3f}{t / n * 1e6:12.2f}{t / t_par:9.1f}x{t * FULL_STUDY / n / 60:18.1f} min')
    return 0


if __name__ == '__main__':
    sys.exit(main())
