"""Critical-plane search over a 10,000-point grid and one cycle (issue 14 budget: <= 2 s, 2 cores).

The stress cycle is the closed-form Cattaneo-Mindlin / Nowell-Hills field of a fretting rig
(:class:`fretbem.fatigue.CattaneoMindlinCycle`) on a 100 x 100 grid below the contact, over
the last full reversal (``--steps`` load steps); the stresses are computed once, outside the
timing. Timed: :func:`fretbem.fatigue.critical_plane_parameters` for each parameter alone and
for all four together, 3D plane search (default) and in-plane only. Median of ``--runs``
runs after one warm-up; machine information is printed first.

Run from the repository root::

    python benchmarks/fatigue_grid.py
    python benchmarks/fatigue_grid.py --steps 20 --runs 7 --json fatigue_bench.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time

import numpy as np

from fretbem.fatigue import (
    DEFAULT_METHODS,
    CattaneoMindlinCycle,
    PlaneSearch,
    critical_plane_parameters,
    last_full_reversal,
)

E, NU = 116000.0, 0.342
CONSTANTS = {"findley_k": 0.3, "fatemi_socie_k": 0.5, "yield_strength": 941.8}


def stress_cycle(n_points_side: int, steps: int) -> np.ndarray:
    """(steps, n^2, 4) stress over the last full reversal on an n x n grid below the contact."""
    branch = max(2, (steps - 1) // 4)
    cm = CattaneoMindlinCycle(
        a=0.5,
        p0=300.0,
        f=0.6,
        tangential_ratio=0.5,
        sigma_bulk_max=80.0,
        nu=NU,
        steps_per_branch=branch,
    )
    x = np.linspace(-0.75, 0.75, n_points_side)
    z = np.linspace(0.0, 0.5, n_points_side)
    X, Z = np.meshgrid(x, z)
    stress = cm.stress_at(np.stack([X.ravel(), Z.ravel()], axis=1))
    return stress[last_full_reversal(cm.driver)]


def timed(fn, runs: int) -> tuple[list[float], list[float]]:
    """Wall-clock and process CPU times of ``runs`` calls after one warm-up.

    On a shared machine the CPU time shows the work done; the wall time includes waiting.
    """
    fn()  # warm-up
    wall, cpu = [], []
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--side", type=int, default=100, help="grid points per side (100 -> 10,000)"
    )
    parser.add_argument("--steps", type=int, default=9, help="load steps in the cycle (5-20)")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", help="write the medians here")
    args = parser.parse_args()
    print(
        f"machine: {platform.platform()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, load average {os.getloadavg()[0]:.1f}"
    )
    stress = stress_cycle(args.side, args.steps)
    print(f"grid {stress.shape[1]} points, cycle of {stress.shape[0]} steps")
    cases = [(m,) for m in DEFAULT_METHODS] + [DEFAULT_METHODS]
    results = {}
    for in_plane in (False, True):
        search = PlaneSearch(in_plane_only=in_plane)
        for methods in cases:
            name = ("in-plane " if in_plane else "3D ") + "+".join(methods)
            times, cpu = timed(
                lambda methods=methods, search=search: critical_plane_parameters(
                    stress, E=E, nu=NU, methods=methods, search=search, **CONSTANTS
                ),
                args.runs,
            )
            med = statistics.median(times)
            results[name] = {"wall_s": med, "cpu_s": statistics.median(cpu)}
            print(
                f"  {name:<42s} wall median {med:6.3f} s (min {min(times):.3f}), "
                f"CPU median {statistics.median(cpu):6.3f} s"
            )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(
                {
                    "points": int(stress.shape[1]),
                    "steps": int(stress.shape[0]),
                    "median_s": results,
                },
                fh,
                indent=2,
            )


if __name__ == "__main__":
    main()
