"""CPU per Newton iteration of the 61-pair reference cycle, before and after, interleaved.

Each round runs a fresh process per tree (``PYTHONPATH`` the tree's ``framework`` and
``plugins``, one BLAS thread), trees alternating; a process prepares ``--cycles`` scenes
of each body model (BEM bodies, half-plane bodies) and times their five steps and, inside
them, the solver's increments (CPU), after a warm-up run on another pad. Medians of the
cycles per process, then of the rounds.

    git archive 14d358e | tar -x -C /tmp/newton-before
    OPENBLAS_NUM_THREADS=1 python benchmarks/newton_iteration_cost.py \\
        --before /tmp/newton-before --rounds 4 --json docs/results/newton_iteration_cost.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, statistics, sys, time
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton
spent = {"seconds": 0.0, "iterations": 0}
solve = newton.SemiSmoothNewton.solve_increment
def timed(self, *args, **kwargs):
    start = time.process_time()
    result = solve(self, *args, **kwargs)
    spent["seconds"] += time.process_time() - start
    spent["iterations"] += result.iterations
    return result
newton.SemiSmoothNewton.solve_increment = timed
out = {}
for name, models in {"halfplane": {"upper": "half-plane", "lower": "half-plane"},
                     "bem": {}}.items():
    run(scenes.cattaneo_mindlin(pairs=61, models=models, radius=71.0))
    simulations = [scenes.cattaneo_mindlin(pairs=61, models=models)
                   for _ in range(int(sys.argv[1]))]
    for simulation in simulations:
        simulation.prepare()
    per, steps = [], []
    for simulation in simulations:
        spent.update(seconds=0.0, iterations=0)
        start = time.process_time()
        run(simulation)
        steps.append(time.process_time() - start)
        per.append(spent["seconds"] / spent["iterations"])
    out[name] = {"per_iteration": statistics.median(per), "steps": statistics.median(steps),
                 "iterations": spent["iterations"]}
print(json.dumps(out))
"""


def one(tree: Path, cycles: int) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}")  # fmt: skip
    text = subprocess.run([sys.executable, "-c", CHILD, str(cycles)], env=env, check=True,
                          capture_output=True, text=True).stdout  # fmt: skip
    return json.loads(text.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--after", type=Path, default=ROOT)
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--cycles", type=int, default=15)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    load = [os.getloadavg()[0]]
    runs: dict[str, list] = {k: [] for k in trees}
    for k in range(args.rounds):
        for label, tree in trees.items():
            runs[label].append(one(tree, args.cycles))
        print(f"round {k + 1} done, load {os.getloadavg()[0]:.2f}", flush=True)
    load.append(os.getloadavg()[0])
    result = {"load": load, "rounds": args.rounds, "cycles": args.cycles}
    for label, rounds in runs.items():
        result[label] = {
            model: {
                key: statistics.median(r[model][key] for r in rounds) for key in rounds[0][model]
            }
            for model in rounds[0]
        }
    for model in ("halfplane", "bem"):
        b, a = result["before"][model], result["after"][model]
        print(f"{model:9s}: {1e6 * b['per_iteration']:.0f} -> {1e6 * a['per_iteration']:.0f} us "
              f"per iteration, steps {1e3 * b['steps']:.1f} -> {1e3 * a['steps']:.1f} ms, "
              f"iterations {b['iterations']:.0f} / {a['iterations']:.0f}")  # fmt: skip
    if args.json:
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
