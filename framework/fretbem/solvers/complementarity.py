"""One contact increment as a linear complementarity problem, solved by Lemke's method.

In 2D, Coulomb friction is exactly linear complementarity (Klarbring 1990): split the slip
increment s = s+ - s- (s+, s- >= 0) and pair

    p  >= 0  with  g = deformed gap          >= 0,
    s+ >= 0  with  f p - q                    >= 0,   (slip forward only at q = +f p)
    s- >= 0  with  f p + q                    >= 0.   (slip backward only at q = -f p)

The shear q is eliminated through the tangential relation (its compliance block is
invertible), and each loading-block displacement d = d+ - d- is paired with its force
balance written as two inequalities, R - F >= 0 and F - R >= 0, so that the whole
increment is one LCP(M, c) in z = (p, s+, s-, d+, d-). Lemke's pivoting method then finds
the exact solution of the piecewise-linear problem in finitely many pivots, by a path
that shares nothing with the semi-smooth Newton iteration: which is what makes it a
cross-check of Newton's answers and a fallback when Newton cycles.
"""

from __future__ import annotations

import attrs
import numpy as np

from .lemke import solve_lcp

SEPARATED, STICK, SLIP = 0, 1, 2


@attrs.frozen(eq=False)
class CondensedArrays:
    """The affine maps of one increment, in x = (p, q, block displacements).

    Attributes
    ----------
    normal_map, tangential_map : ndarray, shape (n, n_x)
        Relative normal / tangential displacement per unit of x.
    normal_base, tangential_base : ndarray, shape (n,)
        Their values at x = 0 (including any load columns of this increment).
    resultant_map : ndarray, shape (k, n_x); resultant_base : ndarray, shape (k,)
        Loading-block resultant forces.
    gap : ndarray, shape (n,)
        Initial normal gap.
    """

    normal_map: np.ndarray
    tangential_map: np.ndarray
    normal_base: np.ndarray
    tangential_base: np.ndarray
    resultant_map: np.ndarray
    resultant_base: np.ndarray
    gap: np.ndarray

    @property
    def n_pairs(self) -> int:
        """Number of node pairs."""
        return len(self.gap)


@attrs.frozen(eq=False)
class LcpIncrement:
    """Solution of one increment: x = (p, q, block displacements), pair states, pivots."""

    x: np.ndarray
    states: np.ndarray
    pivots: int
    residual: float


def solve_lcp_increment(
    arrays: CondensedArrays,
    *,
    friction: float,
    forces: np.ndarray,
    reference_slip: np.ndarray,
    max_pivots: int | None = None,
) -> LcpIncrement:
    """Solve one contact increment exactly by Lemke's method (see the module docstring)."""
    n = arrays.n_pairs
    n_x = arrays.normal_map.shape[1]
    k = n_x - 2 * n
    forces = np.asarray(forces, dtype=float)
    p_cols, q_cols, d_cols = slice(0, n), slice(n, 2 * n), slice(2 * n, n_x)
    t_map = arrays.tangential_map
    t0 = arrays.tangential_base - np.asarray(reference_slip, dtype=float)
    # scales of the LCP rows and columns: tractions tau, displacements c tau, and forces
    # per pair (tau times a pair's resultant weight), which makes the coupling of a block
    # displacement with the gaps and slips nearly skew to that of the tractions with the
    # force balance: M stays close to copositive, where Lemke's method cannot end on a ray
    force_scale = max(np.max(np.abs(forces), initial=0.0), 1e-300)
    weights = np.abs(arrays.resultant_map[:, p_cols]).sum(axis=1) if k else np.ones(1)
    tau = force_scale / max(weights.max(initial=0.0), 1e-300)
    force_scale = tau * max(weights.max(initial=0.0), 1e-300) / n
    compliance = np.mean(np.abs(np.diag(arrays.normal_map[:, p_cols])))
    length = compliance * tau
    # z = (p, b+, b-, lam, d+, d-) in scaled units, q = b+ - b-, lam = |s|; x = X z (+ 0)
    size = 4 * n + 2 * k
    columns = np.zeros((n_x, size))
    columns[p_cols, :n] = np.eye(n) * tau
    columns[q_cols, n : 2 * n] = np.eye(n) * tau
    columns[q_cols, 2 * n : 3 * n] = -np.eye(n) * tau
    columns[d_cols, 4 * n : 4 * n + k] = np.eye(k) * length
    columns[d_cols, 4 * n + k :] = -np.eye(k) * length
    lam = slice(3 * n, 4 * n)
    matrix = np.zeros((size, size))
    base = np.zeros(size)
    # p: deformed gap
    matrix[:n] = arrays.normal_map @ columns / length
    base[:n] = (arrays.gap + arrays.normal_base) / length
    # b+: lam - s >= 0, b-: lam + s >= 0 (s the slip increment)
    slip_rows = t_map @ columns / length
    matrix[n : 2 * n], base[n : 2 * n] = -slip_rows, -t0 / length
    matrix[2 * n : 3 * n], base[2 * n : 3 * n] = slip_rows, t0 / length
    matrix[n : 3 * n, lam] = np.vstack([np.eye(n), np.eye(n)])
    # lam: f p - b+ - b- >= 0
    matrix[lam, :n] = friction * np.eye(n)
    matrix[lam, n : 2 * n] = matrix[lam, 2 * n : 3 * n] = -np.eye(n)
    # d+: R - F >= 0, d-: F - R >= 0
    balance = (arrays.resultant_base - forces) / force_scale
    force_rows = arrays.resultant_map @ columns / force_scale
    matrix[4 * n : 4 * n + k], base[4 * n : 4 * n + k] = force_rows, balance
    matrix[4 * n + k :], base[4 * n + k :] = -force_rows, -balance
    solution = solve_lcp(matrix, base, max_pivots=max_pivots)
    x = columns @ solution.z
    p = x[p_cols]
    slipping = solution.z[lam] > 0
    states = np.where(p > 0, np.where(slipping, SLIP, STICK), SEPARATED)
    residual = float(np.max(np.abs(np.minimum(solution.w, 0.0)), initial=0.0))
    residual = max(residual, float(np.max(np.abs(solution.z * solution.w), initial=0.0)))
    return LcpIncrement(x, states, solution.pivots, residual)
