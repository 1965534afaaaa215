"""The chunked row sums of the rigid-body identity equal numpy's strided sum bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.bem.assembly import _row_sums


@pytest.mark.parametrize("n", [1, 7, 31, 139, 333])
@pytest.mark.parametrize("chunk", [1, 5, 64])
def test_row_sums_equal_the_strided_sum_bit_for_bit(n, chunk):
    # values of mixed magnitudes and signs, where a different order of the sum would show
    rng = np.random.default_rng(n)
    h = rng.normal(size=(2 * n, 2 * n)) * 10.0 ** rng.integers(-8, 8, size=(2 * n, 2 * n))
    expected = h.reshape(n, 2, n, 2).sum(axis=2)
    got = _row_sums(h, n, chunk=chunk)
    assert got.shape == (n, 2, 2)
    np.testing.assert_array_equal(got, expected)
