"""The BEM reference cycle's steps with two trees' Newton linear algebra, in one process.

``fretbem.solvers.newton_linear`` is loaded from the ``--before`` tree beside this tree's
and the two alternate round by round on one prepared scene per pair count (BEM bodies),
each run on a new solver; CPU ms of the five steps, medians, the iterations per step and
the largest difference of the unknowns relative to the largest pressure (changes to the
Newton step's arithmetic must keep it below 1e-10 and the iterations equal).

    OPENBLAS_NUM_THREADS=1 python benchmarks/newton_trees.py --before /tmp/before \\
        --pairs 61 481 --rounds 9
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import attrs
import numpy as np
from tree_module import tree_module

from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton, newton_linear
from fretbem.solvers.newton import SemiSmoothNewton


def _module(tree: Path):
    """The tree's newton_linear module, under a name of its own."""
    return tree_module(tree, "fretbem.solvers.newton_linear", "newton_linear_before")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--pairs", type=int, nargs="+", default=[61, 481])
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args()
    classes = {"before": _module(args.before).NewtonLinear, "after": newton_linear.NewtonLinear}
    kept = newton.NewtonLinear
    print(f"load {os.getloadavg()[0]:.2f}")
    try:
        for pairs in args.pairs:
            prepared = scenes.cattaneo_mindlin(pairs=pairs, models={})
            prepared.prepare()
            times: dict[str, list[float]] = {name: [] for name in classes}
            results = {}
            for _ in range(args.rounds):
                for name, linear in classes.items():
                    newton.NewtonLinear = linear
                    simulation = attrs.evolve(prepared, solver=SemiSmoothNewton())
                    start = time.process_time()
                    results[name] = run(simulation)
                    times[name].append(time.process_time() - start)
            before = results["before"].steps
            for name in classes:
                steps = results[name].steps
                scale = max(np.max(np.abs(s.pressure)) for s in before)
                moved = max(np.max(np.abs(a.x - b.x)) for a, b in zip(before, steps, strict=True))
                print(f"{pairs} pairs, {name}: steps {statistics.median(times[name]) * 1e3:.1f} "
                      f"ms, iterations {[s.iterations for s in steps]}, unknowns moved "
                      f"{moved / scale:.1e} of p_max")  # fmt: skip
    finally:
        newton.NewtonLinear = kept
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
