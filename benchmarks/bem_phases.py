"""The BEM reference cycle by phase, two source trees interleaved (issue 28 item 3).

Each round runs one fresh process per tree (``PYTHONPATH`` = the tree's ``framework`` and
``plugins``, one BLAS thread); in it, at 61 and 481 pairs, ``--cycles`` cold cycles (scene
cache cleared) with BEM bodies, each split into the scene build, the assembly of both
bodies' H and G, the rest of ``prepare`` (factorisation, contact responses, condensation)
and the five steps, each followed by the numpy Toeplitz peer
(``benchmarks/halfplane_peer.py``); CPU seconds, medians over cycles and rounds, and the
median ratio of cycle to peer. As in ``benchmarks/workflows.py``, each pair count first
runs a cycle on another pad (imports; at 481 pairs numba's compiled loops), so the 61-pair
cycle assembles with the numpy loops and the 481-pair one with the compiled loops.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_phases.py --before /tmp/before \\
        --rounds 3 --cycles 5
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
import json, sys, time
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
import halfplane_peer
from cold_caches import clear_scene_caches
out = {}
for pairs in map(int, sys.argv[3].split(",")):
    run(scenes.cattaneo_mindlin(pairs=pairs, models={}, radius=71.0))  # imports: another pad
    rows = []
    for _ in range(int(sys.argv[2])):
        clear_scene_caches()
        start = time.process_time()
        simulation = scenes.cattaneo_mindlin(pairs=pairs, models={})
        built = time.process_time()
        simulation.pair.upper.matrices()
        simulation.pair.lower.matrices()
        assembled = time.process_time()
        simulation.prepare()
        prepared = time.process_time()
        run(simulation)
        done = time.process_time()
        halfplane_peer.cycle(pairs)
        rows.append((built - start, assembled - built, prepared - assembled, done - prepared,
                     done - start, time.process_time() - done))
    out[pairs] = rows
print(json.dumps(out))
"""
PHASES = ("build", "assembly", "rest of prepare", "steps", "total", "peer")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True, help="source tree of the old code")
    parser.add_argument("--after", type=Path, default=ROOT, help="source tree of the new code")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cycles", type=int, default=5)
    parser.add_argument("--pairs", default="61,481", help="comma-separated pair counts")
    args = parser.parse_args()
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    counts = args.pairs.split(",")
    rows: dict[str, dict[str, list]] = {name: {p: [] for p in counts} for name in trees}
    load = [os.getloadavg()[0]]
    for _ in range(args.rounds):
        for name, tree in trees.items():
            path = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
            env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=path)
            text = subprocess.run(
                [sys.executable, "-c", CHILD, str(ROOT / "benchmarks"), str(args.cycles),
                 args.pairs],
                env=env, capture_output=True, text=True, check=True,
            ).stdout  # fmt: skip
            for pairs, values in json.loads(text.strip().splitlines()[-1]).items():
                rows[name][pairs] += values
    load.append(os.getloadavg()[0])
    print(f"load {load[0]:.2f} -> {load[1]:.2f}; CPU ms, medians of "
          f"{args.rounds} rounds x {args.cycles} cycles")  # fmt: skip
    for pairs in counts:
        for name in trees:
            values = rows[name][pairs]
            medians = [statistics.median(v[i] for v in values) * 1e3 for i in range(6)]
            ratio = statistics.median(v[4] / v[5] for v in values)
            text = ", ".join(f"{p} {m:6.1f}" for p, m in zip(PHASES, medians, strict=True))
            print(f"{name:6s} {pairs:>3s} pairs: {text}; cycle / peer {ratio:.2f}")


if __name__ == "__main__":
    main()
