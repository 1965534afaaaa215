"""The face's banded operator E: its tiled product and chunked E^T solves give the same
bits as the plain diagonal loop and ``scipy.linalg.solve_banded`` they replace."""

import numpy as np
import pytest
import scipy.linalg as sla

from fretbem.bem.system import _Band, face_values_matrix
from fretbem.scenes.reference import cattaneo_mindlin


def banded(n: int, lower: int, upper: int, seed: int = 0) -> np.ndarray:
    """A random banded matrix that needs row pivoting (small diagonal)."""
    rng = np.random.default_rng(seed)
    matrix = np.zeros((n, n))
    for d in range(-lower, upper + 1):
        matrix += np.diag(rng.uniform(0.5, 1.5, n - abs(d)), d)
    matrix[np.arange(n), np.arange(n)] *= 0.1
    return matrix


def diagonal_loop(matrix: np.ndarray, x: np.ndarray, lower: int, upper: int) -> np.ndarray:
    """E @ x one whole diagonal at a time (the previous implementation)."""
    n = len(matrix)
    out = np.zeros(x.shape)
    for d in range(-lower, upper + 1):
        diagonal = np.diagonal(matrix, d)[:, None]
        if d >= 0:
            out[: n - d] += diagonal * x[d:]
        else:
            out[-d:] += diagonal * x[: n + d]
    return out


def transposed_bands(matrix: np.ndarray, lower: int, upper: int) -> np.ndarray:
    n = len(matrix)
    bands = np.zeros((lower + upper + 1, n))
    for d in range(-lower, upper + 1):
        diagonal = np.diagonal(matrix, -d)
        if d >= 0:
            bands[upper - d, d:] = diagonal
        else:
            bands[upper - d, : n + d] = diagonal
    return bands


@pytest.mark.parametrize(("n", "lower", "upper", "cols"), [
    (61, 2, 2, 244), (200, 2, 2, 9000), (97, 1, 1, 300), (50, 1, 3, 70), (1, 0, 0, 5),
])  # fmt: skip
def test_band_product_and_solves_are_bit_identical(n, lower, upper, cols):
    matrix = banded(n, lower, upper)
    band = _Band(matrix)
    x = np.random.default_rng(1).standard_normal((n, cols))
    assert np.array_equal(band.left(x), diagonal_loop(matrix, x, band.lower, band.upper))
    rhs = np.asfortranarray(np.random.default_rng(2).standard_normal((n, cols)))
    bands = transposed_bands(matrix, band.upper, band.lower)
    expected = sla.solve_banded((band.upper, band.lower), bands, rhs.copy(order="F"))
    for _ in range(2):  # the second solve reuses the factorisation
        assert np.array_equal(band.solve_transposed(rhs.copy(order="F")), expected)
    assert np.allclose(matrix.T @ expected, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())


def test_reference_face_band():
    """The reference face's E (quadratic NURBS, five diagonals) on a (n, 2, 2, n) array."""
    pair = cattaneo_mindlin(pairs=61).pair
    matrix = face_values_matrix(pair.upper, pair.upper_tag)
    band = _Band(matrix)
    n = band.size
    x = np.random.default_rng(3).standard_normal((n, 2, 2, n))
    expected = diagonal_loop(matrix, x.reshape(n, -1), band.lower, band.upper)
    assert np.array_equal(band.left(x), expected.reshape(x.shape))


@pytest.mark.parametrize(("n", "lower", "upper"), [(40, 2, 2), (37, 1, 3), (33, 3, 1), (25, 0, 2),
                                                   (30, 1, 1), (1, 0, 0)])  # fmt: skip
def test_row_by_row_solve_matches_the_column_solve(n, lower, upper):
    """E^-T on node-major right-hand sides, row by row, with LAPACK's pivoted band LU: the
    column solve's numbers to round-off (the same operations, possibly fused there)."""
    matrix = banded(n, lower, upper, seed=n)
    band = _Band(matrix)
    rhs = np.random.default_rng(n).standard_normal((n, 7))
    rows = band.solve_transposed_rows(rhs.copy())
    residual = matrix.T @ rows - rhs  # backward stable: small against |E^T| |y|
    assert np.max(np.abs(residual)) <= 1e-14 * np.max(np.abs(matrix.T) @ np.abs(rows))
    if n > 1 and lower + upper > 2:  # a pivoted LU (the tridiagonal case uses gtsv)
        columns = _Band(matrix).solve_transposed(rhs.copy(order="F"))
        assert np.max(np.abs(rows - columns)) <= 4e-15 * np.max(np.abs(columns))
