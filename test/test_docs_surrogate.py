"""The surrogate tables of the docs are what full runs of the surrogate scenes print now.

``tools/docs.py --check surrogate surrogate-estimator``: the six surrogate scenes (catenary,
taut and locked reel on JONSWAP and on HPR 2) and ``surrogate_estimator``, 120 s each, in a
file of their own so that the test run gives them a worker of their own beside test_docs.py's
full run of the default scene.
"""

from __future__ import annotations

from test_docs import _check


def test_the_surrogate_tables_are_what_full_runs_of_the_surrogate_scenes_print(tmp_path):
    result = _check(['surrogate', 'surrogate-estimator'], tmp_path, 1800)
    assert result.returncode == 0, result.stderr[-4000:]
