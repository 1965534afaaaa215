"""A 60-line numpy influence-coefficient peer of the reference cycle (issue 28's yardstick).

Two identical elastic half-planes (plane strain, so normal and tangential problems uncouple)
pressed by P with the reference scene's relative radius, then loaded by the steps' Q: constant
tractions on ``pairs`` equal strips over 1.5 Hertz half-widths each side, collocated at the strip
centres; the influence matrix of the log kernel is Toeplitz. Active sets for contact (pressure
>= 0) and for stick/slip (|q| <= f p, slip against the shear), as the BEM solver decides them.
It does what the half-plane body model does in the least numpy: the half-plane model's cost
over this is the price of its generality.

    python benchmarks/halfplane_peer.py 61     # prints the time and the Hertz/Mindlin errors
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.linalg import solve, toeplitz

E, NU, RADIUS, F, P = 73400.0, 0.33, 70.0, 0.3, 100.0
Q_STEPS = (0.0, 18.0, 0.0, -18.0, 0.0)


def cycle(pairs: int):
    """Pressure, shear (steps, pairs) and the nodes of the reference cycle."""
    e_star, r_star = E / (2.0 * (1.0 - NU**2)), RADIUS / 2.0
    a = np.sqrt(4.0 * P * r_star / (np.pi * e_star))
    x = np.linspace(-1.5 * a, 1.5 * a, pairs)
    h = x[1] - x[0]

    def prim(t):  # integral of ln|t|
        return t * np.log(np.where(t == 0.0, 1.0, np.abs(t))) - t

    d = x - x[0]
    K = -2.0 / (np.pi * e_star) * toeplitz(prim(d + h / 2) - prim(d - h / 2))

    def solve_set(rows, fixed, rhs_total):
        """Unknowns on ``rows`` and the rigid term: K t - c = rhs there, sum(t) h = total."""
        n = rows.sum()
        A = np.zeros((n + 1, n + 1))
        A[:n, :n], A[:n, n], A[n, :n] = K[np.ix_(rows, rows)], -1.0, h
        b = np.concatenate([fixed[0][rows] - K[np.ix_(rows, ~rows)] @ fixed[1][~rows],
                            [rhs_total - h * fixed[1][~rows].sum()]])  # fmt: skip
        return solve(A, b)

    touch = np.abs(x) < a
    for _ in range(50):  # normal: K p - delta = -x^2 / 2R on the contact, p = 0 elsewhere
        p = np.zeros(pairs)
        sol = solve_set(touch, (-(x**2) / (2 * r_star), p), P)
        p[touch] = sol[:-1]
        gap = x**2 / (2 * r_star) + K @ p - sol[-1]
        new = (touch & (p > 0)) | (~touch & (gap < 0))
        if np.array_equal(new, touch):
            break
        touch = new
    pressures, shears = [], []
    u_old = np.zeros(pairs)
    for Q in Q_STEPS:
        stick, sign = touch.copy(), np.zeros(pairs)
        for _ in range(100):  # tangential: no slip increment on stick, |q| = f p on slip
            q = np.where(stick, 0.0, sign * F * p)
            sol = solve_set(stick, (u_old, q), Q)
            q[stick] = sol[:-1]
            slip = K @ q - sol[-1] - u_old
            over = stick & (np.abs(q) > F * p * (1 + 1e-12))
            back = ~stick & touch & (sign * slip > 0)  # friction must oppose the slip: sticks
            if not over.any() and not back.any():
                break
            sign = np.where(over, np.sign(q), sign)
            stick = (stick & ~over) | back
        u_old = u_old + slip
        pressures.append(p.copy())
        shears.append(q.copy())
    return x, np.array(pressures), np.array(shears), a


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 61
    cycle(n)
    t = time.perf_counter()
    x, p, q, a = cycle(n)
    seconds = time.perf_counter() - t
    p0 = 2 * P / (np.pi * a)
    hertz = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    c = a * np.sqrt(1 - Q_STEPS[1] / (F * P))
    mindlin = F * p0 * (np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
                        - c / a * np.sqrt(np.clip(1 - (x / c) ** 2, 0, None)))  # fmt: skip
    print(f"{n} pairs: {seconds * 1e3:.1f} ms; max |p - Hertz| / p0 = "
          f"{np.abs(p[1] - hertz).max() / p0:.3f}, max |q_B - Mindlin| / (f p0) = "
          f"{np.abs(q[1] - mindlin).max() / (F * p0):.3f}")  # fmt: skip
