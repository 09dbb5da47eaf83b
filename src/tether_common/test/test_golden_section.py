"""Golden-section search finds each element's minimum of a unimodal function."""

from __future__ import annotations

import numpy as np

from tether_common.golden_section import golden_section_minimum


def test_minimum_of_shifted_parabolas_elementwise():
    centres = np.array([-1.3, 0.0, 0.25, 2.9])
    calls = []

    def f(x):
        calls.append(x.shape)
        return (x - centres) ** 2 + np.cosh(x - centres)

    found = golden_section_minimum(f, np.full(4, -5.0), np.full(4, 5.0), iterations=70)
    np.testing.assert_allclose(found, centres, atol=1e-6)  # sqrt(machine epsilon) of a smooth minimum
    assert len(calls) == 72 and all(shape == (4,) for shape in calls)


def test_scalar_bracket_gives_a_scalar():
    found = golden_section_minimum(lambda x: np.abs(x - 0.7), 0.0, 1.0)
    assert found.shape == () and abs(float(found) - 0.7) < 1e-10  # a kink: located to the bracket width
