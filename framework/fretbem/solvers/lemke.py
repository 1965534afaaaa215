"""Lemke's complementary pivoting method for the linear complementarity problem LCP(M, q).

Find z >= 0 with w = M z + q >= 0 and w . z = 0 (Lemke 1965; Cottle, Pang and Stone, The
Linear Complementarity Problem, 1992, sec. 4.4). The method follows a path of almost
complementary basic solutions from the artificial start z0 = -min(q) (covering vector of
ones) and stops when z0 leaves the basis. Ties in the ratio test are broken
lexicographically, which rules out cycling on degenerate problems.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.errors import ComputationError


class LemkeError(ComputationError):
    """Lemke's method ended on a secondary ray or ran out of pivots: no solution found."""


#: the message for an LCP whose entries are not finite numbers
_NOT_FINITE = (
    "the contact problem has entries that are not finite numbers (a load, stiffness or "
    "compliance beyond the floating-point range): Lemke's method cannot solve it; check the "
    "scene's loads and stiffnesses for values far outside their physical range"
)


@attrs.frozen(eq=False)
class LcpSolution:
    """z and w = M z + q of a solved LCP, and the number of pivots taken.

    Attributes
    ----------
    z, w : ndarray, shape (N,)
    pivots : int
    """

    z: np.ndarray
    w: np.ndarray
    pivots: int


def solve_lcp(m: np.ndarray, q: np.ndarray, *, max_pivots: int | None = None) -> LcpSolution:
    """Solve LCP(M, q) by complementary pivoting on a dense tableau.

    Raises LemkeError on ray termination (the LCP may have no solution, or M is not of a
    class Lemke's method is guaranteed to process) or after ``max_pivots`` (default 50 N).
    """
    m = np.asarray(m, dtype=float)
    q = np.asarray(q, dtype=float)
    n = len(q)
    if m.shape != (n, n):
        raise ValueError(f"solve_lcp: M must be square with the size of q ({n}), got {m.shape}")
    if not (np.all(np.isfinite(m)) and np.all(np.isfinite(q))):
        raise LemkeError(_NOT_FINITE)
    if np.all(q >= 0.0):
        return LcpSolution(np.zeros(n), q.copy(), 0)
    max_pivots = 50 * n if max_pivots is None else int(max_pivots)
    # tableau columns: w (n, the initial basis), z (n), z0, right-hand side; rows: B^-1 [...]
    tableau = np.zeros((n, 2 * n + 2))
    tableau[:, :n] = np.eye(n)
    tableau[:, n : 2 * n] = -m
    tableau[:, 2 * n] = -1.0
    tableau[:, -1] = q
    basis = np.arange(n)  # variable index basic in each row: w_i = i, z_i = n + i, z0 = 2 n
    z0 = 2 * n
    scale = max(np.max(np.abs(m), initial=0.0), np.max(np.abs(q)), 1e-300)
    tol = 1e-12 * scale
    # first pivot: z0 enters where q is most negative (lexicographic on ties)
    row = _lexicographic_min(tableau, np.arange(n), -tableau[:, 2 * n], n, tol, first=True)
    entering = z0
    for pivots in range(1, max_pivots + 1):
        leaving = basis[row]
        _pivot(tableau, row, entering)
        basis[row] = entering
        if leaving == z0:
            return _solution(tableau, basis, n, m, q, pivots)
        entering = leaving + n if leaving < n else leaving - n  # the complement enters
        column = tableau[:, entering]
        candidates = np.flatnonzero(column > tol * 1e-3)
        if candidates.size == 0:
            raise LemkeError(
                f"Lemke's method ended on a ray after {pivots} pivots (the entering variable "
                "can grow without bound): no solution was found; the problem may have none "
                "(e.g. loads beyond the sliding limit), or use the Newton solver"
            )
        # z0 leaves at once if it ties for the minimum ratio: that ends the path
        row = _lexicographic_min(tableau, candidates, column, n, tol, prefer=basis == z0)
    raise LemkeError(
        f"Lemke's method did not finish in {max_pivots} pivots (LCP of size {n}); raise "
        "max_pivots or use the Newton solver"
    )


def _lexicographic_min(tableau, candidates, column, n, tol, *, first=False, prefer=None):
    """Row of the lexicographically smallest (rhs, B^-1 row) / column over ``candidates``."""
    rhs = tableau[candidates, -1]
    ratios = rhs / column[candidates]
    best = ratios.min()
    # ratios within round-off of the minimum tie (the rhs is O(scale); entries O(column))
    tied = candidates[ratios <= best + tol * 1e-3 / max(np.abs(column[candidates]).min(), 1e-300)]
    if first:
        tied = candidates[rhs <= rhs.min() + tol * 1e-3]
    if prefer is not None and np.any(prefer[tied]):
        return int(tied[np.argmax(prefer[tied])])
    # lexicographic order on the rows of B^-1 (the tableau's w columns) over the column entry:
    # each pass jumps to the first column on which the tied rows differ
    while tied.size > 1:
        values = tableau[tied, :n] / column[tied, None]
        spread = values.max(axis=0) - values.min(axis=0)
        scale = 1e-14 * max(np.abs(values).max(), 1.0)
        differ = np.flatnonzero(spread > scale)
        if differ.size == 0:
            break
        k = differ[0]
        tied = tied[values[:, k] <= values[:, k].min() + scale]
    if tied.size == 0:  # NaN ratios: the tableau overflowed while pivoting
        raise LemkeError(_NOT_FINITE)
    return int(tied[0])


def _pivot(tableau: np.ndarray, row: int, column: int) -> None:
    """Gauss-Jordan pivot on (row, column) in place."""
    pivot_row = tableau[row] / tableau[row, column]
    tableau -= np.outer(tableau[:, column], pivot_row)
    tableau[row] = pivot_row


def _solution(tableau, basis, n, m, q, pivots) -> LcpSolution:
    values = np.zeros(2 * n + 1)
    values[basis] = tableau[:, -1]
    z = np.maximum(values[n : 2 * n], 0.0)
    return LcpSolution(z, m @ z + q, pivots)
