"""added_at: np.add.at on zeros, bit for bit, and its refusals."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.numerics.scatter import added_at


@pytest.mark.parametrize("seed", range(5))
def test_added_at_equals_add_at_bit_for_bit(seed):
    """Repeated indices summed in the same order: the same numbers as np.add.at, for one
    axis and for two (rows broadcast against columns), values of very different sizes."""
    rng = np.random.default_rng(seed)
    for n, k in ((1, 0), (7, 50), (40, 700)):
        index = rng.integers(0, n, size=(k, 3))
        values = rng.standard_normal((k, 3)) * 10.0 ** rng.integers(-8, 9, size=(k, 3))
        expected = np.zeros(n)
        np.add.at(expected, index, values)
        assert np.array_equal(added_at(n, index, values), expected)
        rows = rng.integers(0, 5, size=(k, 1))
        expected = np.zeros((5, n))
        np.add.at(expected, (rows, index), values)
        assert np.array_equal(added_at((5, n), (rows, index), values), expected)


def test_added_at_refuses_an_index_outside():
    with pytest.raises(IndexError, match="outside"):
        added_at(3, np.array([0, 3]), np.ones(2))
    with pytest.raises(IndexError, match="outside"):
        added_at(3, np.array([-1]), np.ones(1))
    with pytest.raises(IndexError, match="outside"):
        added_at((2, 2), (np.array([2]), np.array([0])), np.ones(1))
