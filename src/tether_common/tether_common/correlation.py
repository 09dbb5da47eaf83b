"""Normalised cross-correlation of two series at every lag, the same bits whatever the machine's threads.

``np.correlate`` and ``np.dot`` hand long series to BLAS, whose dot product splits a sum over
more than 10,000 terms across its threads: the last bits then depend on how many threads it
may use (a Ray worker allows one, a shell two), so a report's figure would differ between a
campaign's run and the same run alone. The correlation here goes through numpy's FFT, which
uses no threads.
"""

from __future__ import annotations

import numpy as np


def cross_correlation(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lags k (samples, ``-(n-1)..n-1``) and ``Σ_i x_i y_(i+k) / (n σ_x σ_y)`` at each, means removed.

    A positive lag is ``y`` following ``x``. 0 at every lag when either series is constant.
    """
    x = np.asarray(x, dtype=float) - np.mean(x)
    y = np.asarray(y, dtype=float) - np.mean(y)
    n = len(x)
    lags = np.arange(-(n - 1), n)
    scale = n * np.std(x) * np.std(y)
    if not scale > 0:
        return lags, np.zeros(2 * n - 1)
    size = 1 << (2 * n - 1).bit_length()
    circular = np.fft.irfft(np.fft.rfft(y, size) * np.conj(np.fft.rfft(x, size)), size)
    return lags, np.concatenate([circular[size - (n - 1):], circular[:n]]) / scale
