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


@pytest.mark.parametrize("n", [1, 7, 139, 333])
@pytest.mark.parametrize("half", [False, True])
def test_compiled_row_sums_equal_the_numpy_ones_bit_for_bit(n, half):
    """The compiled loops' row sums, read in place (every row, or a mirrored body's
    integrated rows only), equal the chunked numpy sums to the last bit."""
    pytest.importorskip("numba")
    from fretbem.bem import compiled_loops, numpy_loops
    from fretbem.bem.assembly import _rigid_row_sums

    rng = np.random.default_rng(n + 1)
    h = rng.normal(size=(2 * n, 2 * n)) * 10.0 ** rng.integers(-8, 8, size=(2 * n, 2 * n))
    h[0, 0] = -0.0  # a signed zero first: kept as numpy keeps it
    integrated = rng.random(n) < 0.5 if half else None
    expected = _rigid_row_sums(numpy_loops, h, n, integrated)
    got = _rigid_row_sums(compiled_loops, h, n, integrated)
    np.testing.assert_array_equal(got, expected)
    assert np.array_equal(np.signbit(got), np.signbit(expected))
    if half:
        assert not got[~integrated].any()
