"""The tiled C-to-Fortran copy of the collocation matrix is an exact copy."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.bem.system import _fortran_copy


@pytest.mark.parametrize("shape", [(1, 1), (5, 5), (1030, 1030), (700, 1300)])
def test_tiled_copy_is_exact_and_fortran_ordered(shape):
    matrix = np.random.default_rng(0).normal(size=shape)
    copy = _fortran_copy(matrix, tile=256)
    assert copy.flags.f_contiguous
    np.testing.assert_array_equal(copy, matrix)
    copy[0, 0] += 1.0
    assert copy[0, 0] != matrix[0, 0]  # a copy, not a view


def test_fortran_input_is_copied_too():
    matrix = np.asfortranarray(np.arange(12.0).reshape(3, 4))
    copy = _fortran_copy(matrix)
    np.testing.assert_array_equal(copy, matrix)
    assert copy.flags.f_contiguous and not np.shares_memory(copy, matrix)
