"""Unloading steps of a fine contact: no pair reverses its slip in one Newton step.

With the pair spacing h, the augmentation r_t grows like 1 / (h log h) and the stick window
of the trial traction, 2 f p / r_t, shrinks below the slip a Newton step produces. Before
reversing pairs were taken through stick (once the residual grows), the unloading steps C
and E of the half-plane cycle at 481 pairs drained their stick zone to an all-slip, singular
pattern: 223 iterations (4 failed 50-iteration attempts and the sub-steps) where 121 pairs
need 5.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.contact.law import PairState
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}


@pytest.mark.parametrize("pairs", [121, 481])
def test_halfplane_unloading_converges_without_substeps(pairs):
    """Each step of the half-plane cycle converges in one short Newton run (measured
    121 pairs: 9/5/6/5/6; 481 pairs: 11/8/9/7/9, and 223 for C and E before), and the
    unloading steps have Mindlin's stick zone |x| < a sqrt(1 - (Q_B - Q) / (2 f P))."""
    result = run(cattaneo_mindlin(pairs=pairs, models=HALF_PLANES))
    iterations = [s.iterations for s in result.steps]
    assert max(iterations) <= 15, iterations
    a = result.steps[0].x[result.steps[0].states != PairState.SEPARATED].max()
    h = np.diff(result.steps[0].x).max()
    expected = a * np.sqrt(1.0 - 18.0 / (2 * 0.3 * 100.0))
    for step in (result.steps[2], result.steps[4]):
        stick = step.x[step.states == PairState.STICK]
        assert abs(np.abs(stick).max() - expected) <= 2 * h + 0.02 * a, (stick.max(), expected)


def test_coarse_cycles_keep_the_plain_iteration():
    """At 61 pairs the residual never grows, so both body models keep their iterations."""
    bem = run(cattaneo_mindlin(pairs=61))
    halfplane = run(cattaneo_mindlin(pairs=61, models=HALF_PLANES))
    assert [s.iterations for s in bem.steps] == [8, 5, 5, 4, 5]
    assert [s.iterations for s in halfplane.steps] == [8, 5, 4, 4, 4]
