"""The lean uncoupled Newton iteration against the general one, in one process (issue 28).

The half-plane reference cycle's increments (61 pairs by default, two half-planes of one
material) are recorded once, then solved again and again by fresh SemiSmoothNewton
solvers: through the lean iteration (``fretbem.solvers.newton_uncoupled``) and through the
general path (NewtonLinear and the law's evaluation, ``LEAN_BELOW = 0``), alternating
round by round. CPU ms per cycle (the solver's increments only, per-problem set-up
included), medians; the largest difference of the unknowns over p_max and the iterations.

    OPENBLAS_NUM_THREADS=1 python benchmarks/uncoupled_newton.py --pairs 21 61 --rounds 60
"""

from __future__ import annotations

import argparse
import copy
import os
import statistics
import time

import numpy as np

from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton, newton_uncoupled

HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}
LEAN_BELOW = newton_uncoupled.LEAN_BELOW


def increments(pairs: int, basis: str) -> list:
    """Every solve_increment call of one cycle: (solver, problem, law, keyword arguments)."""
    calls = []
    solve = newton.SemiSmoothNewton.solve_increment

    def recorded(self, problem, law, **kwargs):
        calls.append((copy.copy(self), problem, law, kwargs))
        return solve(self, problem, law, **kwargs)

    newton.SemiSmoothNewton.solve_increment = recorded
    try:
        run(scenes.cattaneo_mindlin(pairs=pairs, basis=basis, models=HALF_PLANES))
    finally:
        newton.SemiSmoothNewton.solve_increment = solve
    return calls


def cycle(calls: list, lean: bool) -> tuple[float, list]:
    """CPU seconds of the cycle's increments on a fresh solver, and their results."""
    newton_uncoupled.LEAN_BELOW = LEAN_BELOW if lean else 0
    solver = copy.copy(calls[0][0])
    start = time.process_time()
    results = [solver.solve_increment(problem, law, **kwargs) for _, problem, law, kwargs in calls]
    seconds = time.process_time() - start
    newton_uncoupled.LEAN_BELOW = LEAN_BELOW
    return seconds, results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[61])
    parser.add_argument("--basis", default="nurbs")
    parser.add_argument("--rounds", type=int, default=60)
    args = parser.parse_args()
    load = os.getloadavg()[0]
    for pairs in args.pairs:
        calls = increments(pairs, args.basis)
        times = {"general": [], "lean": []}
        for _ in range(args.rounds):
            for label in times:
                seconds, results = cycle(calls, label == "lean")
                times[label].append(seconds)
                if label == "lean":
                    lean = results
                else:
                    general = results
        scale = max(np.abs(r.x[:pairs]).max() for r in general)
        difference = max(np.abs(a.x - b.x).max() for a, b in zip(lean, general, strict=True))
        medians = {k: 1e3 * statistics.median(v) for k, v in times.items()}
        print(
            f"{pairs} pairs ({args.basis}): general {medians['general']:.2f} ms, lean "
            f"{medians['lean']:.2f} ms, lean / general {medians['lean'] / medians['general']:.2f}"
            f"; iterations {[r.iterations for r in general]} -> {[r.iterations for r in lean]}"
            f"; unknowns within {difference / scale:.1e} of p_max"
        )
    print(f"load average {load:.1f} -> {os.getloadavg()[0]:.1f}, {args.rounds} rounds")


if __name__ == "__main__":
    main()
