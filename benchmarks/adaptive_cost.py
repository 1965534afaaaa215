"""The adaptive mode's cost against a fixed run of its budget (issue 28), in one process.

The reference scene (``cattaneo_mindlin``), CPU seconds of, interleaved round by round:

- ``fixed``: a bare fixed 61-pair run (scene built, assembled, five steps);
- ``fixed+estimate``: the fixed mode with its estimate (:func:`fretbem.accuracy.modes.solve`,
  ``Accuracy(mesh="fixed")``: the 61-pair run and its 31-pair companion level);
- ``adaptive``: the adaptive mode at budget 61 (``Accuracy(mesh="adaptive", budget=61)``,
  the default tolerance: the levels the budget allows, each settled).

Everything runs once before the rounds (imports, compiled kernels, caches of the process);
the medians of ``--rounds`` rounds and the ratios adaptive / fixed+estimate (the target: at
most 3) and adaptive / fixed are printed. Within a round the fixed runs take most of their
H and G blocks from the block store (:data:`fretbem.bem.assembly.BLOCKS`: the scene
builder hands out the same segments, and fixed+estimate's 61 pairs follow the fixed run's),
while the adaptive levels' re-meshed faces are new; ``--cold`` empties the block store and
the scene builder's cache before every workload, as for a scene's first run in a process.
Before and after: run it with ``PYTHONPATH`` pointing at each tree::

    git archive 2e517d6 | tar -x -C /tmp/fat-before
    PYTHONPATH=/tmp/fat-before/framework:/tmp/fat-before/plugins OPENBLAS_NUM_THREADS=1 \\
        python benchmarks/adaptive_cost.py
    PYTHONPATH=framework:plugins OPENBLAS_NUM_THREADS=1 python benchmarks/adaptive_cost.py
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

from fretbem.accuracy.modes import Accuracy, solve
from fretbem.bem import assembly
from fretbem.scenes import builder, cattaneo_mindlin
from fretbem.simulation import run


def cases(budget: int) -> dict:
    """The three workloads, each building its scene from scratch."""
    return {
        "fixed": lambda: run(cattaneo_mindlin(pairs=budget)),
        "fixed+estimate": lambda: solve(cattaneo_mindlin(pairs=budget), Accuracy(mesh="fixed")),
        "adaptive": lambda: solve(
            cattaneo_mindlin(pairs=budget), Accuracy(mesh="adaptive", budget=budget)
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=int, default=61)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--json", help="write the medians and ratios here")
    parser.add_argument(
        "--cold", action="store_true", help="no H/G blocks or scenes kept between workloads"
    )
    args = parser.parse_args()
    work = cases(args.budget)
    for fn in work.values():  # warm-up: imports, kernels
        fn()
    load = [os.getloadavg()[0]]
    times: dict[str, list[float]] = {name: [] for name in work}
    for _ in range(args.rounds):
        for name, fn in work.items():
            if args.cold:
                assembly.BLOCKS.clear()
                builder._built.cache_clear()
            start = time.process_time()
            fn()
            times[name].append(time.process_time() - start)
    load.append(os.getloadavg()[0])
    medians = {name: statistics.median(values) for name, values in times.items()}
    ratios = {
        "adaptive / fixed+estimate": medians["adaptive"] / medians["fixed+estimate"],
        "adaptive / fixed": medians["adaptive"] / medians["fixed"],
    }
    for name, value in medians.items():
        print(f"{name:16s} {value:.4f} s CPU")
    for name, value in ratios.items():
        print(f"{name:28s} {value:.2f}")
    print(f"load average {load[0]:.1f} -> {load[1]:.1f}")
    if args.json:
        with open(args.json, "w") as fh:
            record = {"medians": medians, "ratios": ratios, "load": load, "cold": args.cold}
            json.dump(record, fh, indent=1)


if __name__ == "__main__":
    main()
