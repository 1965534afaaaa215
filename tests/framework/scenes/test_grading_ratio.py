"""The flank grading ratio's bisection stops once its bracket is two adjacent floats: the
ratio of the full 80 steps, bit for bit."""

from __future__ import annotations

import math

import pytest

from fretbem.scenes.builder import grading_ratio


def _eighty_steps(length: float, elements: int, smallest: float) -> float:
    """Frozen copy of the bisection before its early stop: 80 steps always."""
    target = smallest * elements / length
    if target >= 1.0:
        return 1.0
    lo, hi = 1e-9, math.log(1e6)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid / math.expm1(mid) > target else (lo, mid)
    return math.exp(0.5 * (lo + hi))


@pytest.mark.parametrize("length", [0.3, 2.0, 17.5, 480.0])
@pytest.mark.parametrize("elements", [1, 4, 12, 60])
@pytest.mark.parametrize("smallest", [1e-7, 1e-4, 0.01, 0.2, 5.0])
def test_early_stop_gives_the_eighty_step_ratio(length, elements, smallest):
    ratio = grading_ratio(length, elements, smallest)
    assert ratio == _eighty_steps(length, elements, smallest)
    if smallest * elements < length and ratio < 0.999e6:  # graded, below the 1e6 cap:
        # ln(r) / (r - 1) hits the density
        r = math.log(ratio)
        assert r / math.expm1(r) == pytest.approx(smallest * elements / length, rel=1e-9)
