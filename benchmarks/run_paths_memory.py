"""Kept memory on every run path: a large wear history and a large finite-sliding run, CPU
(user + system) and peak memory against another tree, each run in a fresh process.

A run of at least ``KEPT_MEMORY_DOFS`` (2,048) boundary DOFs keeps its freed large arrays
on the heap (:mod:`fretbem.numerics.memory`) instead of having the kernel map and zero
them afresh each time; before it was applied to every run path only ``run()`` had it. The
runs: ``examples/fretting_wear_sliding_bem.toml`` on fixed pairs (``run_wear``, 481 pairs,
2,236 DOFs, 20 cycles) and ``examples/gross_sliding_bem.toml`` (``run_sliding``, 121
pairs, 2,946 DOFs, 1 + 6 + 6 increments). The trees are interleaved run by run; medians
over ``--rounds``, the load average (``os.getloadavg``) before every round; the results'
bytes are hashed, so equal hashes mean bit-identical results (unknowns of every sliding
step; every wear snapshot's pressure and both depth profiles).

Run from the repository root::

    git archive 37ea6f4 | tar -x -C /tmp/before
    OPENBLAS_NUM_THREADS=1 python benchmarks/run_paths_memory.py --before /tmp/before --rounds 3
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

#: (name, scene file, pairs, kind, wear cycles)
RUNS = (
    ("wear", "examples/fretting_wear_sliding_bem.toml", 481, "wear", 20),
    ("sliding", "examples/gross_sliding_bem.toml", 121, "sliding", 0),
)

CHILD = """
import hashlib, json, resource, sys, tomllib
import numpy as np
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
path, pairs, kind, cycles = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
with open(path, "rb") as handle:
    data = tomllib.load(handle)
data["contact"]["pairs"] = pairs
for table in ("wear", "stress", "fatigue"):
    data.pop(table, None)
if kind == "sliding":
    data["load"]["increments"] = [1, 6, 6]
else:
    data["contact"]["sliding"] = False
simulation = build(scene_from_data(data))[0]
dofs = int(simulation.pair.upper.dofs + simulation.pair.lower.dofs)
before = resource.getrusage(resource.RUSAGE_SELF)
digest = hashlib.sha256()
if kind == "sliding":
    from fretbem.sliding.slide import run_sliding
    for step in run_sliding(simulation, note=None).steps:
        digest.update(np.ascontiguousarray(step.unknowns).tobytes())
else:
    from fretbem.wear.law import EnergyWear
    from fretbem.wear.run import WearSimulation, run_wear
    laws = {"upper": EnergyWear(1.775e-4), "lower": EnergyWear(1.775e-4)}
    for snap in run_wear(WearSimulation(simulation, laws, cycles)).snapshots:
        for array in (snap.pressure, snap.profile.upper, snap.profile.lower):
            digest.update(np.ascontiguousarray(array).tobytes())
after = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({"dofs": dofs, "user": after.ru_utime - before.ru_utime,
                  "sys": after.ru_stime - before.ru_stime, "peak_mib": after.ru_maxrss / 1024,
                  "hash": digest.hexdigest()[:16]}))
"""


def one_run(tree: Path, scene: str, pairs: int, kind: str, cycles: int) -> dict:
    """One run in a fresh process with ``tree``'s fretbem first on the path."""
    env = {
        **os.environ,
        "OPENBLAS_NUM_THREADS": "1",
        "PYTHONPATH": f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}",
    }
    done = subprocess.run(
        [sys.executable, "-c", CHILD, str(ROOT / scene), str(pairs), kind, str(cycles)],
        capture_output=True, text=True, env=env, cwd=tree,
    )  # fmt: skip
    if done.returncode:
        sys.exit(f"{kind} in {tree} failed:\n{done.stderr.strip()}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", required=True, help="the other source tree")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    trees = {"before": Path(args.before).resolve(), "after": ROOT}
    rows: dict[tuple[str, str], list[dict]] = {}
    for round_ in range(args.rounds):
        print(json.dumps({"round": round_ + 1, "load": os.getloadavg()[0]}), flush=True)
        for name, scene, pairs, kind, cycles in RUNS:
            for label, tree in trees.items():
                rows.setdefault((name, label), []).append(one_run(tree, scene, pairs, kind, cycles))
    for name, *_ in RUNS:
        summary = {"run": name, "dofs": rows[(name, "after")][0]["dofs"]}
        for label in trees:
            runs = rows[(name, label)]
            summary[label] = {
                key: round(statistics.median(r[key] for r in runs), 3)
                for key in ("user", "sys", "peak_mib")
            }
            summary[label]["cpu"] = round(statistics.median(r["user"] + r["sys"] for r in runs), 3)
            summary[label]["sys_runs"] = [round(r["sys"], 2) for r in runs]
        hashes = {r["hash"] for label in trees for r in rows[(name, label)]}
        summary["bit_identical"] = len(hashes) == 1
        summary["cpu_ratio"] = round(summary["after"]["cpu"] / summary["before"]["cpu"], 3)
        print(json.dumps(summary), flush=True)


if __name__ == "__main__":
    main()
