"""Large problems: the reference cycle at 61 to 1921 pairs, per phase, with its peak memory.

Every run is a fresh process (so ``ru_maxrss`` is that run's own peak) that builds
``cattaneo_mindlin(pairs=...)`` and runs the whole five-step cycle; it reports the phases of
``SimulationResult.timings`` (assembly, factorisation, condensation with the factorisation
inside it, steps, total from the start of ``run``), the CPU seconds of ``run`` (user and
system: the cycle's own cost when other work shares the cores), the scene construction,
the boundary DOFs of both bodies, the Newton iterations and the peak resident memory. Runs
of the sizes are interleaved and each size's numbers are medians over ``--runs``; the load
average (``os.getloadavg``) before and after every run is printed with them, since the
machine is shared. BLAS runs on one thread (``--blas-threads``). One JSON line per size.

Targets (issue 16): 961 pairs, whole cycle <= 4 s; 1921 pairs (``--largest``, one run by
default) <= 20 s and <= 1.5 GiB peak.

Run from the repository root::

    python benchmarks/large_problems.py                  # 61 241 481 961, 3 runs, ~2 min
    python benchmarks/large_problems.py --largest        # and 1921 once
    python benchmarks/large_problems.py --sizes 961 --runs 5 --json large.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

SIZES = (61, 241, 481, 961)
LARGEST = 1921
TARGETS = {961: {"total": 4.0}, 1921: {"total": 20.0, "peak_rss_mib": 1536.0}}
PHASES = ("assembly", "factorisation", "condensation", "steps", "total")

CHILD = """
import json, os, resource, sys, time
tic = time.perf_counter()
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
imported = time.perf_counter()
simulation = cattaneo_mindlin(pairs=int(sys.argv[1]))
built = time.perf_counter()
_before = resource.getrusage(resource.RUSAGE_SELF)
cpu_before = _before.ru_utime + _before.ru_stime
result = run(simulation)
usage = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps({
    "dofs": int(simulation.pair.upper.dofs + simulation.pair.lower.dofs),
    "build": built - imported,
    **result.timings,
    "iterations": [step.iterations for step in result.steps],
    "cpu": usage.ru_utime + usage.ru_stime - cpu_before,
    "peak_rss_mib": usage.ru_maxrss / 1024,
}))
"""


def load() -> float:
    """One-minute load average (nan where unavailable)."""
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:  # pragma: no cover
        return float("nan")


def one_run(pairs: int, blas_threads: int) -> dict:
    """One cycle at ``pairs`` in a fresh process, with the load before and after."""
    threads = str(blas_threads)
    env = {**os.environ, "OPENBLAS_NUM_THREADS": threads, "MKL_NUM_THREADS": threads}
    before = load()
    done = subprocess.run(
        [sys.executable, "-c", CHILD, str(pairs)], capture_output=True, text=True, env=env
    )
    if done.returncode:
        sys.exit(f"the run at {pairs} pairs failed:\n{done.stderr.strip()}")
    return {**json.loads(done.stdout.strip().splitlines()[-1]), "load": (before, load())}


def summary(pairs: int, runs: list[dict]) -> dict:
    """Medians of the runs at one size, with every run's load and the targets met."""
    row = {"pairs": pairs, "dofs": runs[0]["dofs"], "runs": len(runs)}
    for key in ("build", *PHASES, "cpu", "peak_rss_mib"):
        row[key] = round(statistics.median(run[key] for run in runs), 3)
    row["cpu_runs"] = [round(run["cpu"], 2) for run in runs]  # each run's, in order
    row["iterations"] = runs[0]["iterations"]
    if any(run["iterations"] != row["iterations"] for run in runs):  # pragma: no cover
        row["iterations_differ"] = [run["iterations"] for run in runs]
    row["load"] = [run["load"] for run in runs]
    targets = TARGETS.get(pairs, {})
    if targets:
        row["targets"] = {key: [limit, row[key] <= limit] for key, limit in targets.items()}
    return row


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    parser.add_argument("--runs", type=int, default=3, help="runs per size (median)")
    parser.add_argument("--largest", action="store_true", help=f"add {LARGEST} pairs")
    parser.add_argument("--largest-runs", type=int, default=1)
    parser.add_argument("--blas-threads", type=int, default=1)
    parser.add_argument("--json", help="also write the JSON lines to this file")
    args = parser.parse_args(argv)
    print(json.dumps({"cores": os.cpu_count(), "blas_threads": args.blas_threads,
                      "python": sys.version.split()[0]}), flush=True)  # fmt: skip
    one_run(min(args.sizes), args.blas_threads)  # warm-up: compiled kernels cached on disk
    results: dict[int, list[dict]] = {pairs: [] for pairs in args.sizes}
    for _ in range(args.runs):  # interleaved, so a burst of load spreads over the sizes
        for pairs in args.sizes:
            results[pairs].append(one_run(pairs, args.blas_threads))
    if args.largest:
        results[LARGEST] = [one_run(LARGEST, args.blas_threads) for _ in range(args.largest_runs)]
    lines = [json.dumps(summary(pairs, runs)) for pairs, runs in results.items()]
    print("\n".join(lines), flush=True)
    if args.json:
        with open(args.json, "w") as handle:
            handle.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
