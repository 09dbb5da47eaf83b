"""The modified Twiddle algorithm of thesis Sec. 5.2 (Algorithm 1) for the filter covariances.

Coordinate descent: each parameter P(i) is tried at P(i) + dP(i), then at P(i) - dP(i); a
better cost grows the step by 10 %, a worse one shrinks it by 10 %; the loop ends when the
mean relative step (1/m) sum dP(i)/P(i) falls to ``tolerance`` (0.1 in the thesis). The
thesis limits a step to 50 % of its parameter so that no covariance goes negative; here
the step is capped at ``max_step`` = 45 % of the current value before each trial, so the
trial P(i) - dP(i) stays at least 55 % of P(i), strictly positive.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def twiddle(cost: Callable[[np.ndarray], float], p: np.ndarray, dp: np.ndarray, tolerance: float = 0.1,
            max_step: float = 0.45, max_rounds: int = 100,
            progress: Callable[[int, float, np.ndarray], None] | None = None) -> tuple[np.ndarray, float, int]:
    """Minimise ``cost`` over positive parameters; return (best parameters, best cost, rounds run)."""
    p = np.array(p, dtype=float)
    dp = np.minimum(np.array(dp, dtype=float), max_step * p)
    best = cost(p)
    rounds = 0
    while np.mean(dp / p) > tolerance and rounds < max_rounds:
        for i in range(p.size):
            dp[i] = min(dp[i], max_step * p[i])
            p[i] += dp[i]
            q = cost(p)
            if q < best:
                best = q
                dp[i] *= 1.1
                continue
            p[i] -= 2.0 * dp[i]
            q = cost(p)
            if q < best:
                best = q
                dp[i] *= 1.1
                continue
            p[i] += dp[i]
            dp[i] *= 0.9
        rounds += 1
        if progress is not None:
            progress(rounds, best, p.copy())
    return p, best, rounds
