"""The half-plane cycle's steps with the split Newton factor against the coupled one below
``SPLIT_FROM`` unknowns (issue 28 item 3).

Two identical half-planes uncouple the normal problem from the tangential one, and
``fretbem.solvers.newton_linear`` then factorises the normal block (kept while the contact
set holds) and the tangential block apart. Under ``SPLIT_FROM`` unknowns the products keep
their plain form; this compares the split factor there with the coupled LU the solver used
before (``normal_part`` refused below ``SPLIT_FROM``). One process, one prepared reference
scene per pair count, the two alternating run by run on a new solver each; CPU ms of the
five steps, medians, the iterations per step (equal for both) and the largest difference of
the unknowns (round-off: the two factorisations order the arithmetic differently).

    OPENBLAS_NUM_THREADS=1 python benchmarks/split_small_systems.py --pairs 61 121 181 --rounds 40

(From 200 pairs the system has SPLIT_FROM unknowns or more, where both split.) Both run
through NewtonLinear: the lean iteration that small uncoupled problems take by default
(``fretbem.solvers.newton_uncoupled``, benchmarks/uncoupled_newton.py) is switched off.
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
from fretbem.solvers import newton_linear, newton_uncoupled
from fretbem.solvers.newton import SemiSmoothNewton

MODELS = {"upper": "half-plane", "lower": "half-plane"}


def _coupled_below_split(normal_map, tangential_map, resultant_map):
    """The solver's rule before: no split factor under SPLIT_FROM unknowns."""
    if normal_map.shape[1] < newton_linear.SPLIT_FROM:
        return None
    return _split(normal_map, tangential_map, resultant_map)


_split = newton_linear.normal_part


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[61, 121, 181])
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.2f}")
    rules = {"split": _split, "coupled": _coupled_below_split}
    lean_below, newton_uncoupled.LEAN_BELOW = newton_uncoupled.LEAN_BELOW, 0
    try:
        for pairs in args.pairs:
            prepared = scenes.cattaneo_mindlin(pairs=pairs, models=MODELS)
            prepared.prepare()
            times: dict[str, list[float]] = {name: [] for name in rules}
            iterations: dict[str, list[int]] = {}
            unknowns: dict[str, list[np.ndarray]] = {}
            for _ in range(args.rounds):
                for name, rule in rules.items():
                    newton_linear.normal_part = rule
                    simulation = attrs.evolve(prepared, solver=SemiSmoothNewton())
                    start = time.process_time()
                    result = run(simulation)
                    times[name].append(time.process_time() - start)
                    iterations[name] = [s.iterations for s in result.steps]
                    unknowns[name] = [np.asarray(s.unknowns) for s in result.steps]
            difference = max(
                float(np.max(np.abs(a - b)))
                for a, b in zip(unknowns["split"], unknowns["coupled"], strict=True)
            )
            medians = {name: statistics.median(t) * 1e3 for name, t in times.items()}
            ratio = medians["split"] / medians["coupled"]
            print(f"{pairs} pairs: steps split {medians['split']:.2f} ms, coupled "
                  f"{medians['coupled']:.2f} ms, ratio {ratio:.2f}; iterations "
                  f"{iterations['split']} and {iterations['coupled']}; unknowns within "
                  f"{difference:.2g}")  # fmt: skip
    finally:
        newton_linear.normal_part = _split
        newton_uncoupled.LEAN_BELOW = lean_below
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
