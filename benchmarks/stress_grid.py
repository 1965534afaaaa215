"""Stresses on a 10,000-point grid below the contact, every step of the reference cycle
(issue 13 budget: <= 1 s on the 2-core CI machine).

The reference scene (61 pairs) is solved once, outside the timing. Timed, for the lower
body: building the Somigliana evaluation matrix of a 100 x 100 grid over x in [-2a, 2a]
and depth [0, 3a] (rows graded toward the surface, the first row on the surface) and
evaluating all five steps (one matrix product each), through
:class:`fretbem.stress.StressEvaluator`. Also reported: the split of the build into the
far-field loop and the near band (points within one element length of an element), and
the cost per point-element pair. Median of ``--runs`` runs after one warm-up (which also
loads numba's cache); machine information is printed first.

Run from the repository root::

    python benchmarks/stress_grid.py
    python benchmarks/stress_grid.py --side 100 --runs 5 --json stress_bench.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time

import numpy as np

from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.stress import StressEvaluator, StressSettings
from fretbem.stress.request import StressGrid, grid_points


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=100, help="grid points per side")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", help="write the numbers to this file")
    args = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}")  # fmt: skip

    simulation = cattaneo_mindlin()
    result = run(simulation)
    a = simulation.reference.hertz.half_width
    model = simulation.prepare().pair.side("lower")[0]
    grid = StressGrid(x=(-2 * a, 2 * a), depth=3 * a, nx=args.side, ny=args.side, grading=50.0)
    points = grid_points(model, grid, "lower")[0].reshape(-1, 2)
    n_elements = sum(b.n_elements for b in model.segments)

    def cycle():
        evaluator = StressEvaluator(result, points, "lower")
        return evaluator.steps()

    def build_only(settings):
        return StressEvaluator(result, points, "lower", settings).operator

    cycle()  # warm-up: numba cache, condensation
    times, cpu = [], []
    for _ in range(args.runs):
        start, start_cpu = time.perf_counter(), time.process_time()
        stress = cycle()
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    total = statistics.median(times)
    pairs = len(points) * n_elements
    # the far loop alone: every pair treated as far (no near band, no subtraction)
    far_runs, far_cpu = [], []
    for _ in range(args.runs):
        start, start_cpu = time.perf_counter(), time.process_time()
        build_only(StressSettings(near_factor=1e-12, subtract_factor=0.0))
        far_runs.append(time.perf_counter() - start)
        far_cpu.append(time.process_time() - start_cpu)
    far_only = statistics.median(far_runs)
    numbers = {
        "points": len(points),
        "steps": len(result.steps),
        "elements": n_elements,
        "point_element_pairs": pairs,
        "cycle_seconds_median": total,
        "cycle_seconds_all": times,
        "cycle_cpu_seconds_median": statistics.median(cpu),
        "load_average": os.getloadavg()[0],
        "far_loop_seconds": far_only,
        "far_loop_cpu_seconds": statistics.median(far_cpu),
        "ns_per_pair": 1e9 * total / pairs,
        "stress_shape": list(stress.shape),
    }
    print(
        f"{len(points)} points x {n_elements} elements = {pairs} pairs, {len(result.steps)} steps"
    )
    print(f"build + all steps: median {total:.3f} s over {args.runs} runs "
          f"({1e9 * total / pairs:.0f} ns per point-element pair); process CPU "
          f"{statistics.median(cpu):.3f} s; load average {os.getloadavg()[0]:.1f}")  # fmt: skip
    print(f"far field alone (every pair far, no near band, no subtraction): {far_only:.3f} s "
          f"wall, {statistics.median(far_cpu):.3f} s process CPU")  # fmt: skip
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(numbers, handle, indent=2)


if __name__ == "__main__":
    main()
