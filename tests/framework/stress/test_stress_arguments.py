"""``stresses(result, step, points)`` refuses a bad step or points with one StressInputError:
True is not step 1, and text or an int past a float's range is not a point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.stress import stresses
from fretbem.stress.errors import StressInputError

POINTS = np.array([[0.0, -0.5], [0.1, -0.3]])


@pytest.fixture(scope="module")
def result():
    return run(cattaneo_mindlin(pairs=21))


@pytest.mark.parametrize(
    ("step", "points", "message"),
    [
        (True, POINTS, r"step must be a step's name or index, got True"),
        (10**400, POINTS, r"step an integer of about 10\^400 out of range"),
        (7, POINTS, r"step 7 out of range: the result has 5 steps"),
        ("Z", POINTS, r"no step 'Z'"),
        ("B", "abc", r'points must be .* of numbers, got the string "abc"'),
        ("B", [[10**400, -0.5]], r"points must be .* of numbers, got entries that are not"),
        ("B", [[math.nan, -0.5]], r"points must be a finite array of shape \(m, 2\)"),
        ("B", np.zeros((3, 3)), r"got shape \(3, 3\)"),
    ],
)
def test_a_bad_step_or_points_is_named(result, step, points, message):
    with pytest.raises(StressInputError, match=message):
        stresses(result, step, points)


def test_a_step_by_name_and_by_index_agree(result):
    np.testing.assert_array_equal(stresses(result, "B", POINTS), stresses(result, 1, POINTS))
    np.testing.assert_array_equal(
        stresses(result, "E", POINTS), stresses(result, np.int64(-1), POINTS)
    )
