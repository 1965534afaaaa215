"""The specimen's solve with the pad's kept factors, two trees' ``image_factor`` in one process.

A cold reference cycle (BEM bodies; as in ``bem_phases.py``, after a cycle on another pad,
so that the specimen takes the pad's blocks; ``--integrated``: without it, so that the
specimen is integrated again) is prepared once with the specimen's call to
``solve_as_image`` captured (its matrix, parameter columns and the pad's kept
factorisation); the ``--before`` tree's module and this tree's then solve it in turn, each
on fresh copies of the arrays, and the CPU ms (medians) and the largest difference of
their solutions are printed.

    OPENBLAS_NUM_THREADS=1 python benchmarks/image_solve.py --before /tmp/before --rounds 15
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np
from tree_module import tree_module

from fretbem.bem import image_factor, system
from fretbem.scenes import reference as scenes
from fretbem.simulation import run


def _module(tree: Path):
    return tree_module(tree, "fretbem.bem.image_factor", "image_factor_before")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--pairs", type=int, default=481)
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--integrated", action="store_true", help="no cycle on another pad")
    args = parser.parse_args()
    captured = []
    solve = image_factor.solve_as_image

    def capture(segments, first_dofs, first_rows, image_of, matrix, parameters):
        if image_factor._KEPT[0] is not None:
            captured.append((segments, first_dofs, first_rows, image_of, matrix.copy(order="F"),
                             parameters.copy(order="F"), image_factor._KEPT[0]))  # fmt: skip
        return solve(segments, first_dofs, first_rows, image_of, matrix, parameters)

    if not args.integrated:
        run(scenes.cattaneo_mindlin(pairs=args.pairs, models={}, radius=71.0))
    system.image_factor.solve_as_image = capture
    try:
        scenes.cattaneo_mindlin(pairs=args.pairs, models={}).prepare()
    finally:
        system.image_factor.solve_as_image = solve
    *call, parameters, kept = captured[-1]
    modules = {"before": _module(args.before), "after": image_factor}
    times: dict[str, list[float]] = {name: [] for name in modules}
    out = {}
    print(f"load {os.getloadavg()[0]:.2f}")
    for _ in range(args.rounds):
        for name, module in modules.items():
            module._KEPT[0] = kept
            fresh = parameters.copy(order="F")
            start = time.process_time()
            out[name] = module.solve_as_image(*call, fresh)[0]
            times[name].append(time.process_time() - start)
    for name in modules:
        moved = np.max(np.abs(out[name] - out["before"]))
        print(f"{args.pairs} pairs, {name}: {statistics.median(times[name]) * 1e3:.2f} ms, "
              f"solution moved {moved:.1e}")  # fmt: skip
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
