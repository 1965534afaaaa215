"""Cycle time of each body-model / solver combination on the reference scene (issue 9).

For BEM/BEM, BEM pad on a half-plane specimen and half-plane/half-plane, each with the
semi-smooth Newton and the Lemke solver: the five-step cycle at 61 pairs, in-process, from
building the scene (assembly included) to the last step ("cycle"), and the five steps
alone on the already condensed problem ("steps"). Median of ``--runs`` runs after one
warm-up; the machine's core count and load are printed first.

    python benchmarks/body_solver_combinations.py
    python benchmarks/body_solver_combinations.py --pairs 121 --runs 3 --json out.json
    python benchmarks/body_solver_combinations.py --pairs 241 --runs 3 \
        --performance docs/results/performance.json   # the performance page's comparison
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time

from fretbem.scenes import reference as scenes
from fretbem.simulation import Simulation, run
from fretbem.solvers import LemkeSolver
from fretbem.solvers.newton import SemiSmoothNewton

MODELS = {
    "BEM/BEM": {},
    "BEM/half-plane": {"lower": "half-plane"},
    "half-plane/half-plane": {"upper": "half-plane", "lower": "half-plane"},
}
SOLVERS = {"Newton": SemiSmoothNewton, "Lemke": LemkeSolver}

# the half-plane through the scene factory's body-model hook (kept if already registered)


def _cycle(pairs: int, models: dict, solver) -> tuple[float, float, object]:
    """(whole cycle incl. assembly, steps only) seconds and the result."""
    start = time.perf_counter()
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models=models, solver=solver())
    result = run(simulation)
    whole = time.perf_counter() - start
    again = Simulation(
        simulation.pair, simulation.steps, solver(), law=simulation.law, reference=None
    )
    start = time.perf_counter()
    run(again)
    return whole, time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=61)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", default=None, help="write the table to this file")
    parser.add_argument(
        "--performance",
        default=None,
        help="merge the Newton rows (BEM/BEM against half-plane/half-plane) into this "
        'performance JSON under "halfplane" (benchmarks/performance_page.py)',
    )
    args = parser.parse_args()
    print(
        f"{platform.platform()}, {os.cpu_count()} cores, load average "
        f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}, "
        f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}"
    )
    rows = []
    print(f"{'bodies':24s}{'solver':8s}{'cycle s':>10s}{'steps s':>10s}{'e_q L2':>10s}")
    for label, models in MODELS.items():
        for name, solver in SOLVERS.items():
            _cycle(args.pairs, models, solver)  # warm-up (imports, caches)
            runs = [_cycle(args.pairs, models, solver) for _ in range(args.runs)]
            whole = statistics.median(r[0] for r in runs)
            steps = statistics.median(r[1] for r in runs)
            result = runs[-1][2]
            e_q = max((s.errors or {}).get("e_q_l2", float("nan")) for s in result.steps)
            rows.append(
                {"bodies": label, "solver": name, "cycle_s": whole, "steps_s": steps, "e_q_l2": e_q}
            )
            print(f"{label:24s}{name:8s}{whole:10.3f}{steps:10.3f}{e_q:10.2e}")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump({"pairs": args.pairs, "runs": args.runs, "rows": rows}, handle, indent=1)
    if args.performance:
        _merge_performance(args.performance, args.pairs, rows)


def _merge_performance(path: str, pairs: int, rows: list[dict]) -> None:
    """Add this pair count's Newton cycle of both body models to the performance JSON."""
    newton = {r["bodies"]: r["cycle_s"] for r in rows if r["solver"] == "Newton"}
    with open(path) as handle:
        data = json.load(handle)
    entry = data.setdefault("halfplane", {"cycle": []})
    cycle = [r for r in entry["cycle"] if r["pairs"] != pairs]
    cycle.append(
        {
            "pairs": pairs,
            "bem": newton["BEM/BEM"],
            "halfplane": newton["half-plane/half-plane"],
        }
    )
    entry["cycle"] = sorted(cycle, key=lambda r: r["pairs"])
    with open(path, "w") as handle:
        json.dump(data, handle, indent=1)


if __name__ == "__main__":
    main()
