"""The contact response's banded solve along the node axis: the compiled loop (a process
that has loaded numba) gives the numpy loop's numbers bit for bit, pivoting included, and
both solve E^T y = b."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.bem import system

pytest.importorskip("numba")
from fretbem.bem import compiled_loops  # noqa: F401 - loads numba as the assembly does


@pytest.mark.parametrize(
    ("n", "lower", "upper", "seed"), [(9, 1, 2, 0), (40, 2, 2, 1), (31, 3, 1, 2)]
)
def test_the_compiled_solve_gives_the_numpy_numbers(n, lower, upper, seed, monkeypatch):
    rng = np.random.default_rng(seed)
    matrix = np.zeros((n, n))
    for d in range(-lower, upper + 1):  # a weak diagonal: the band LU pivots
        matrix += np.diag(rng.uniform(0.5, 1.5, n - abs(d)), d)
    matrix[np.arange(n), np.arange(n)] *= 0.1
    rhs = rng.standard_normal((n, 7))
    compiled = system._Band(matrix).solve_transposed_rows(rhs.copy())
    monkeypatch.setattr(system, "_COMPILED", "no such module")
    band = system._Band(matrix)
    assert np.any(band._band_factor()[1] != np.arange(n))  # rows were interchanged
    numpy = band.solve_transposed_rows(rhs.copy())
    assert np.array_equal(compiled, numpy)
    np.testing.assert_allclose(matrix.T @ compiled, rhs, atol=1e-12)
