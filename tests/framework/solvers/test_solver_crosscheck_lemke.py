"""Lemke's complementary pivoting method on small LCPs with known answers."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from fretbem.solvers import LemkeError, solve_lcp


def _enumerate(m: np.ndarray, q: np.ndarray) -> list[np.ndarray]:
    """Every solution of LCP(M, q), by trying each complementary basis (small n only)."""
    n = len(q)
    out = []
    for basic in itertools.product([False, True], repeat=n):
        z_idx = np.flatnonzero(basic)
        z = np.zeros(n)
        if z_idx.size:
            try:
                z[z_idx] = np.linalg.solve(m[np.ix_(z_idx, z_idx)], -q[z_idx])
            except np.linalg.LinAlgError:
                continue
        w = m @ z + q
        if np.all(z >= -1e-12) and np.all(w >= -1e-12):
            out.append(z)
    return out


@pytest.mark.parametrize("seed", range(20))
def test_p_matrix_lcp_matches_enumeration(seed):
    """A P-matrix (here positive definite plus a skew part) has exactly one solution."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 8))
    b = rng.normal(size=(n, n))
    m = b @ b.T + 0.1 * np.eye(n) + (b - b.T)
    q = rng.normal(size=n)
    (expected,) = _enumerate(m, q)
    solution = solve_lcp(m, q)
    np.testing.assert_allclose(solution.z, expected, atol=1e-12)
    np.testing.assert_allclose(solution.w, m @ expected + q, atol=1e-12)
    assert abs(solution.z @ solution.w) < 1e-12


def test_nonnegative_q_needs_no_pivot():
    solution = solve_lcp(np.eye(3), np.array([1.0, 0.0, 2.0]))
    assert solution.pivots == 0
    np.testing.assert_array_equal(solution.z, 0.0)


def test_degenerate_ties_do_not_cycle():
    """Equal ratios everywhere (a degenerate vertex) are broken lexicographically."""
    m = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 2.0], [2.0, 0.0, 1.0]])
    q = np.array([-1.0, -1.0, -1.0])
    solution = solve_lcp(m, q)
    np.testing.assert_allclose(solution.w.min(), 0.0, atol=1e-14)
    assert np.all(solution.z >= 0) and abs(solution.z @ solution.w) < 1e-14
    np.testing.assert_allclose(solution.z, 1.0 / 3.0)


def test_infeasible_lcp_ends_on_a_ray():
    """w = -z - 1 >= 0 has no solution with z >= 0: the path leaves on a ray."""
    with pytest.raises(LemkeError, match="ray"):
        solve_lcp(np.array([[-1.0]]), np.array([-1.0]))


def test_shape_mismatch_is_refused():
    with pytest.raises(ValueError, match="square"):
        solve_lcp(np.eye(2), np.ones(3))
