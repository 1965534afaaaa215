"""The mirror split's half systems in one compiled pass over H and G (numba).

:func:`fretbem.bem.mirror_split.build` reads H and G row chunk by row chunk with a dozen
numpy passes each (gathers, sign products, the symmetry check's differences and maxima,
the halves' sums). This loop makes the same operations per entry in the same order (no
fused multiply-adds: numba compiles without fast-math), so the same half matrices and
contact right-hand sides and the same check. Importing this module imports numba: the
split uses it only once the compiled assembly loops have loaded numba.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True, error_model="numpy")
def build_rows(h, g, rows, which, targets, mirror, sign, solves_u, halves, worst, scale):
    """For each row r of ``rows`` (its halves ``which[r]``: 0 even, 1 odd, 2 both; written at
    row ``targets[r]`` of each): the symmetry check of H's and G's row against the mirrored
    one (``worst``, ``scale``: the largest |M[Q(i), Q(j)] s_i s_j - M[i, j]| and |M[i, j]|,
    updated in place) and the halves' rows ``A[i, D] + t A[i, Q(D)]``, ``G[i, C] + t G[i,
    Q(C)]``. ``halves``: per half (dofs, mirrors, signs, matrix, contact dofs, contact
    mirrors, contact signs, right-hand sides)."""
    n = h.shape[1]
    a_row = np.empty(n)
    for r in range(rows.size):
        row = rows[r]
        other_row = mirror[row]
        row_sign = sign[row]
        for k in range(2):
            matrix = h if k == 0 else g
            for c in range(n):
                kept = matrix[row, c]
                other = (matrix[other_row, mirror[c]] * row_sign) * sign[c] - kept
                if abs(other) > worst[k]:
                    worst[k] = abs(other)
                if abs(kept) > scale[k]:
                    scale[k] = abs(kept)
        for c in range(n):
            a_row[c] = h[row, c] if solves_u[c] else -g[row, c]
        for half in range(2):
            if which[r] != 2 and which[r] != half:
                continue
            dofs, mirrors, signs, out, c_dofs, c_mirrors, c_signs, rhs = halves[half]
            target = targets[r]
            for j in range(dofs.size):
                out[target, j] = a_row[mirrors[j]] * signs[j] + a_row[dofs[j]]
            for j in range(c_dofs.size):
                rhs[target, j] = g[row, c_mirrors[j]] * c_signs[j] + g[row, c_dofs[j]]
