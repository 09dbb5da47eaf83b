"""The cross-correlation against its definition, and the same bits under any BLAS thread count."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np

from tether_common.correlation import cross_correlation


def test_equals_the_definition_at_every_lag():
    rng = np.random.default_rng(3)
    x, y = rng.standard_normal(40), rng.standard_normal(40)
    lags, corr = cross_correlation(x, y)
    a, b = x - x.mean(), y - y.mean()
    for k, value in zip(lags.tolist(), corr):
        direct = sum(a[i] * b[i + k] for i in range(40) if 0 <= i + k < 40) / (40 * a.std() * b.std())
        assert abs(value - direct) < 1e-12


def test_a_series_following_the_other_peaks_at_its_delay():
    rng = np.random.default_rng(4)
    x = rng.standard_normal(500)
    lags, corr = cross_correlation(x, np.roll(x, 7))
    assert lags[np.argmax(corr)] == 7
    assert abs(corr.max() - 1.0) < 0.05


def test_a_constant_series_correlates_nowhere():
    lags, corr = cross_correlation(np.ones(5), np.arange(5.0))
    assert lags.tolist() == [-4, -3, -2, -1, 0, 1, 2, 3, 4]
    assert not corr.any()


PROBE = '''
import hashlib, numpy as np
from tether_common.correlation import cross_correlation
rng = np.random.default_rng(1)
print(hashlib.sha256(cross_correlation(rng.standard_normal(17000), rng.standard_normal(17000))[1].tobytes()).hexdigest())
'''


def test_the_same_bits_with_one_blas_thread_or_two():
    # np.correlate gave different last bits here (17,000 samples, a mission's heave series)
    digests = {subprocess.run([sys.executable, '-c', PROBE], capture_output=True, text=True, check=True,
                              env={**os.environ, 'OPENBLAS_NUM_THREADS': threads, 'OMP_NUM_THREADS': threads}).stdout
               for threads in ('1', '2')}
    assert len(digests) == 1
