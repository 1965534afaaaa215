"""The contact response's banded solve along the node axis in one compiled loop (numba).

:meth:`fretbem.bem.system._Band.solve_transposed_rows` applies LAPACK's band LU of E^T to
node-major right-hand sides a row at a time, each step a numpy update of a few rows
(481 face nodes: about 1,400 small numpy calls). This loop does the same operations per
column in the same order (no fused multiply-adds: numba compiles without fast-math), so
the same numbers. Importing this module imports numba: the contact response uses it only
once the compiled assembly loops have loaded numba (:mod:`fretbem.bem.compiled_loops`).
"""

from __future__ import annotations

import numba


@numba.njit(cache=True, nogil=True, error_model="numpy")
def solve_rows(lu, pivots, lower, upper, rhs):
    """E^-T rhs in place for a C-ordered rhs (n, cols), from gbtrf's ``lu`` and ``pivots``
    (0-based) of E^T with ``lower`` and ``upper`` bandwidths."""
    n, cols = rhs.shape
    band = lower + upper  # U's superdiagonals (row ``band`` of ``lu`` is its diagonal)
    for j in range(n - 1):  # L: the row interchanges and the multipliers, in order
        p = pivots[j]
        if p != j:
            for c in range(cols):
                rhs[j, c], rhs[p, c] = rhs[p, c], rhs[j, c]
        reach = min(lower, n - 1 - j)
        for r in range(1, reach + 1):
            factor = lu[band + r, j]
            for c in range(cols):
                rhs[j + r, c] -= factor * rhs[j, c]
    for j in range(n - 1, -1, -1):  # U, from the last row up
        diagonal = lu[band, j]
        for c in range(cols):
            rhs[j, c] /= diagonal
        for i in range(max(0, j - band), j):
            factor = lu[band - (j - i), j]
            for c in range(cols):
                rhs[i, c] -= factor * rhs[j, c]
    return rhs


@numba.njit(cache=True, nogil=True, error_model="numpy")
def traction_map(indptr, indices, data, solved, out):
    """out[b, k, a, j] = (E solved)[b, k, j, a], E in CSR (``indptr``, ``indices``,
    ``data``) and ``solved`` (n, 2, rows) C-ordered, read at its rows 2 c + k: E @ x along
    the node axis as scipy's CSR product sums it (from 0, the row's entries in stored order;
    no fused multiply-adds), written straight in the traction map's order, where numpy
    copied the strided rows, multiplied and transposed the product (three face-sized
    passes)."""
    n = out.shape[0]
    for a in range(n):  # each row of ``solved`` read whole, in order (a node-major take)
        for j in range(2):
            row = solved[a, j]
            for b in range(n):
                start, stop = indptr[b], indptr[b + 1]
                total_x, total_y = 0.0, 0.0  # k = 0, 1: rows 2 c and 2 c + 1
                for p in range(start, stop):
                    c = 2 * indices[p]
                    total_x += data[p] * row[c]
                    total_y += data[p] * row[c + 1]
                out[b, 0, a, j] = total_x
                out[b, 1, a, j] = total_y
    return out
