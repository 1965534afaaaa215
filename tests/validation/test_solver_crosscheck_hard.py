"""The Lemke solver against Newton on the hard cases: near sliding, extreme friction,
dissimilar bodies (agreement required: 1e-8 f p0; measured 1e-12 .. 7e-12)."""

from __future__ import annotations

import numpy as np
import pytest
from validation_support import cycle, scene

from fretbem.solvers import LemkeSolver

E = 73400.0
AGREEMENT = 1e-8


def _agree(a, b) -> float:
    fp0 = a.simulation.law.friction * max(s.pressure.max() for s in a.steps)
    for x, y in zip(a.steps, b.steps, strict=True):
        np.testing.assert_array_equal(x.states, y.states)
    return max(
        max(np.abs(x.pressure - y.pressure).max(), np.abs(x.shear - y.shear).max()) / fp0
        for x, y in zip(a.steps, b.steps, strict=True)
    )


@pytest.mark.parametrize(
    ("fields", "ratio", "friction"),
    [
        ({}, 0.95, None),
        ({}, 0.99, None),
        ({}, 0.6, 0.02),
        ({}, 0.6, 1.5),
        ({"E_lower": 1000 * E}, 0.6, None),
        ({"E_upper": 1000 * E}, 0.6, None),
    ],
    ids=["Q0.95", "Q0.99", "f0.02", "f1.5", "stiff-lower", "stiff-upper"],
)
def test_lemke_agrees_with_newton_on_hard_cases(fields, ratio, friction):
    base = scene(pairs=61, **fields)
    newton = cycle(base, ratio, friction=friction)
    lemke = cycle(base, ratio, friction=friction, solver=LemkeSolver())
    assert _agree(newton, lemke) < AGREEMENT
