"""The semi-smooth Newton step of the contact solver, reduced to its active rows.

The generalised Jacobian of the Alart-Curnier functions has three kinds of pair rows
(unknowns x = (p, q, block displacements), n pairs):

- separated pair i: identity rows, so dp_i = -F_n[i] and dq_i = -F_t[i];
- slip pair i: the tangential row is c_i times the normal row minus c_i e_i plus e_(n+i),
  c_i = f sign(trial), so with the normal row's equation, dq_i = c_i (dp_i + F_n[i]) - F_t[i];
- contact (stick or slip) normal rows r_n N_i and stick tangential rows -r_t T_i stay.

Eliminating the first two leaves a dense system over (dp of pairs in contact, dq of
sticking pairs, block displacements) only: (n_contact + n_stick + m) unknowns instead of
2 n + m, and the same step to round-off (tests/framework/test_newton_linear.py).
"""

from __future__ import annotations

import numpy as np

#: pair states, as in the contact law (SEPARATED, STICK, SLIP)
_SEPARATED, _STICK, _SLIP = 0, 1, 2


def reduced_newton_step(
    normal_map: np.ndarray,
    tangential_map: np.ndarray,
    resultant_map: np.ndarray,
    residual: np.ndarray,
    states: np.ndarray,
    direction: np.ndarray,
    friction: float,
    r_n: float,
    r_t: float,
) -> np.ndarray:
    """The Newton step dx solving J dx = -F, from the active rows of J only.

    Parameters
    ----------
    normal_map, tangential_map : ndarray, shape (n, n_x)
        Relative normal and tangential displacement per unit of x.
    resultant_map : ndarray, shape (m, n_x)
        Block resultant forces per unit of x (n_x = 2 n + m).
    residual : ndarray, shape (n_x,)
        F = (F_n, F_t, F_b) at the current iterate.
    states : ndarray of int, shape (n,)
        SEPARATED (0), STICK (1) or SLIP (2) of every pair.
    direction : ndarray, shape (n,)
        Sign of the trial tangential traction (used on slipping pairs).
    friction, r_n, r_t : float
        Coulomb coefficient and the normal and tangential augmentation parameters.

    Raises
    ------
    numpy.linalg.LinAlgError
        If the reduced matrix is singular (then so is the full Jacobian).
    """
    n = normal_map.shape[0]
    n_x = normal_map.shape[1]
    f_n, f_t, f_b = residual[:n], residual[n : 2 * n], residual[2 * n :]
    separated = states == _SEPARATED
    contact = ~separated
    stick = states == _STICK
    slip = states == _SLIP
    c = np.flatnonzero(contact)  # dp unknowns
    s = np.flatnonzero(stick)  # dq unknowns
    blocks = np.arange(2 * n, n_x)  # block displacement unknowns
    coeff = friction * direction
    # the known parts of the step: separated pairs, and slip dq's constant term
    step = np.zeros(n_x)
    step[np.flatnonzero(separated)] = -f_n[separated]
    step[n + np.flatnonzero(separated)] = -f_t[separated]
    step[n + np.flatnonzero(slip)] = coeff[slip] * f_n[slip] - f_t[slip]
    # rows kept: normal rows of contact pairs, tangential rows of sticking pairs, resultants
    rows = np.concatenate([r_n * normal_map[c], -r_t * tangential_map[s], resultant_map])
    rhs = -np.concatenate([f_n[c], f_t[s], f_b]) - rows @ step
    # columns: dp of contact pairs (plus c_i x the dq column of a slipping pair i), dq of
    # sticking pairs, block displacements
    matrix_p = rows[:, c]
    slip_in_c = slip[c]
    matrix_p[:, slip_in_c] += rows[:, n + c[slip_in_c]] * coeff[c[slip_in_c]]
    matrix = np.concatenate([matrix_p, rows[:, n + s], rows[:, blocks]], axis=1)
    y = np.linalg.solve(matrix, rhs)
    k_c, k_s = c.size, s.size
    dp = y[:k_c]
    step[c] = dp
    step[n + s] = y[k_c : k_c + k_s]
    step[blocks] = y[k_c + k_s :]
    step[n + c[slip_in_c]] += coeff[c[slip_in_c]] * dp[slip_in_c]
    return step
