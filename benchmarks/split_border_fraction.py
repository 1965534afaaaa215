"""The half-plane cycle's steps against the split factor's border fraction (issue 28 item 3).

``fretbem.solvers.newton_linear.SPLIT_BORDER_FRACTION`` decides when the Newton solve of two
identical half-planes factorises afresh instead of bordering the kept LU. One process, one
prepared reference scene per pair count (half-plane bodies), the fractions alternating round
by round, each run on a new solver (nothing kept between runs); CPU ms of the five steps,
medians, and the iterations per step (which must not depend on the fraction).

    OPENBLAS_NUM_THREADS=1 python benchmarks/split_border_fraction.py --pairs 481 961 \\
        --fractions 0.15 0.1 0.08 0.05 --rounds 7
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import attrs

from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton_linear
from fretbem.solvers.newton import SemiSmoothNewton

MODELS = {"upper": "half-plane", "lower": "half-plane"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[481, 961])
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.15, 0.1, 0.08, 0.05])
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    kept = newton_linear.SPLIT_BORDER_FRACTION
    print(f"load {os.getloadavg()[0]:.2f}")
    try:
        for pairs in args.pairs:
            prepared = scenes.cattaneo_mindlin(pairs=pairs, models=MODELS)
            prepared.prepare()
            times: dict[float, list[float]] = {f: [] for f in args.fractions}
            iterations: dict[float, list[int]] = {}
            for _ in range(args.rounds):
                for fraction in args.fractions:
                    newton_linear.SPLIT_BORDER_FRACTION = fraction
                    simulation = attrs.evolve(prepared, solver=SemiSmoothNewton())
                    start = time.process_time()
                    result = run(simulation)
                    times[fraction].append(time.process_time() - start)
                    iterations[fraction] = [s.iterations for s in result.steps]
            for fraction in args.fractions:
                median = statistics.median(times[fraction]) * 1e3
                print(f"{pairs} pairs, fraction {fraction:g}: steps {median:.1f} ms, "
                      f"iterations {iterations[fraction]}")  # fmt: skip
    finally:
        newton_linear.SPLIT_BORDER_FRACTION = kept
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
