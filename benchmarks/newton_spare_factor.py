"""The BEM cycle's steps with and without the spare Newton factor (issue 28 item 3).

``fretbem.solvers.newton_linear.SPARE_FRACTION`` keeps a factor aside when the next pattern's
system is at most that fraction of its order, and takes it back when a pattern lies closer
to it (the first increment: every pair in contact, a few, every pair again). 0 keeps none,
as before. One process, one prepared reference scene per pair count (BEM bodies), the two
settings alternating round by round, each run on a new solver; CPU ms of the five steps,
medians, and the iterations per step and the largest difference of the unknowns between
the settings (bit for bit: the spare's LU is the one a fresh factorisation makes).

    OPENBLAS_NUM_THREADS=1 python benchmarks/newton_spare_factor.py --pairs 481 961 --rounds 7
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import attrs
import numpy as np

from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton_linear
from fretbem.solvers.newton import SemiSmoothNewton


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[481, 961])
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.0, 0.3])
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    kept = newton_linear.SPARE_FRACTION
    print(f"load {os.getloadavg()[0]:.2f}")
    try:
        for pairs in args.pairs:
            prepared = scenes.cattaneo_mindlin(pairs=pairs, models={})
            prepared.prepare()
            times: dict[float, list[float]] = {f: [] for f in args.fractions}
            iterations: dict[float, list[int]] = {}
            unknowns: dict[float, list[np.ndarray]] = {}
            for _ in range(args.rounds):
                for fraction in args.fractions:
                    newton_linear.SPARE_FRACTION = fraction
                    simulation = attrs.evolve(prepared, solver=SemiSmoothNewton())
                    start = time.process_time()
                    result = run(simulation)
                    times[fraction].append(time.process_time() - start)
                    iterations[fraction] = [s.iterations for s in result.steps]
                    unknowns[fraction] = [s.x for s in result.steps]
            first = unknowns[args.fractions[0]]
            for fraction in args.fractions:
                median = statistics.median(times[fraction]) * 1e3
                pairs_of_steps = zip(first, unknowns[fraction], strict=True)
                moved = max(np.max(np.abs(a - b)) for a, b in pairs_of_steps)
                print(f"{pairs} pairs, spare fraction {fraction:g}: steps {median:.1f} ms, "
                      f"iterations {iterations[fraction]}, unknowns moved {moved:.1e}")  # fmt: skip
    finally:
        newton_linear.SPARE_FRACTION = kept
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
