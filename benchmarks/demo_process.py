"""Whole-process time of ``fretbem demo`` with and without figures and VTK (issues 16, 28).

Each timing is one fresh process (``python -m fretbem.app.cli demo ... --out DIR``: the
console script's ``main()`` on the modules of this interpreter's path); each round runs
every mode and the import floors (bare interpreter, numpy, numpy + scipy.linalg, the CLI's
modules) once, interleaved, and the medians of ``--runs`` rounds are printed with the load
average before and after, wall and CPU, and the demo's CPU over the numpy + scipy.linalg
floor's (issue 28 item 4: at most 4). A per-phase breakdown (wall and CPU) comes from fresh
processes that run ``fretbem.app.cli.main`` as the console script does, after timing the
imports (the CLI, the demo's command module, matplotlib), with timers around every solve
(each module's own ``run`` binding is wrapped: they import it by name), the figures and
the VTK writer. Prints one JSON document. Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/demo_process.py --runs 7 [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

MODES = {"full": [], "bare": ["--no-figures", "--no-vtk"]}
TARGETS = {"full": 1.5, "bare": 0.6}
FLOORS = {
    "python": "pass",
    "numpy": "import numpy",
    "numpy_scipy_linalg": "import numpy, scipy.linalg",
    "fretbem_cli": "import fretbem.app.cli, fretbem.app.commands",
}
PHASES_CHILD = r"""
import time
begin = time.time()
import atexit, gc, json, sys
clock = {"wall": time.perf_counter, "cpu": time.process_time}
spent = {}

def lap(phase, since):
    now = {k: f() for k, f in clock.items()}
    for k in clock:
        spent[f"{phase}_{k}"] = spent.get(f"{phase}_{k}", 0.0) + now[k] - since[k]
    return now

t = {k: f() for k, f in clock.items()}
import fretbem.app.cli
t = lap("import_cli", t)
try:  # as main() does in the console script's process (a tree without it: nothing)
    from fretbem.app.lean_matplotlib import install
    install()
except ImportError:
    pass
import fretbem.app.commands  # the demo's command module: scenes, solvers, writers
t = lap("import_demo", t)
if "--no-figures" not in sys.argv:
    import matplotlib.figure, matplotlib.backends.backend_agg  # the figures' first imports
    t = lap("import_matplotlib", t)
import fretbem.output.figures, fretbem.output.vtk, fretbem.simulation

def timed(module, name, phase):
    inner = getattr(module, name)
    def wrapper(*args, **kwargs):
        since = {k: f() for k, f in clock.items()}
        try:
            return inner(*args, **kwargs)
        finally:
            lap(phase, since)
    wrapper.__wrapped__ = inner
    # every module that imported the function by name (``from fretbem.simulation import
    # run``) calls it through its own global: each such binding is replaced
    for other in list(sys.modules.values()):
        if getattr(other, name, None) is inner and getattr(other, "__name__", "").startswith(
            "fretbem"
        ):
            setattr(other, name, wrapper)

timed(fretbem.simulation, "run", "solves")
timed(fretbem.output.figures, "save_figures", "figures")
timed(fretbem.output.vtk, "save_vtk", "vtk")
sys.argv = ["fretbem", "demo", *sys.argv[2:], "--out", sys.argv[1]]
t = {k: f() for k, f in clock.items()}

def report():  # an exit handler: the console script's demo ends the process in main()
    lap("main", t)
    for k in clock:
        spent[f"other_{k}"] = spent[f"main_{k}"] - sum(
            spent.get(f"{p}_{k}", 0.0) for p in ("solves", "figures", "vtk")
        )
    spent["cpu_total"] = time.process_time()
    print(json.dumps({**spent, "begin": begin, "end": time.time()}), flush=True)

atexit.register(report)
sys.exit(fretbem.app.cli.main())  # as the console script: argv=None (collector off for demo)
"""


def command() -> list[str]:
    """The demo's command as the console script runs it (``main()`` with no argv: the cyclic
    collector off), from the modules on this interpreter's path: ``python -m
    fretbem.app.cli`` (the ``fretbem`` script would run the installed copy, not a checkout)."""
    return [sys.executable, "-m", "fretbem.app.cli"]


def timed_process(argv: list[str]) -> tuple[float, float]:
    """(wall s, CPU s) of one fresh process (its output discarded; a failure raises)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True)
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return seconds, cpu


def load() -> list[float]:
    return [round(v, 2) for v in os.getloadavg()]


def median(values: list[float]) -> float:
    return round(statistics.median(values), 3)


def whole_process(runs: int, directory: Path) -> dict:
    """Median wall and CPU time per mode and per floor over ``runs`` rounds of fresh
    processes, interleaved (each round runs every mode and floor once), and the demo's CPU
    over the numpy + scipy.linalg floor's, per round (ratios taken in one round)."""
    argvs = {mode: [*command(), "demo", *flags, "--out", str(directory / mode)]
             for mode, flags in MODES.items()}  # fmt: skip
    argvs.update({f"floor_{name}": [sys.executable, "-c", code] for name, code in FLOORS.items()})
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in argvs}
    for k in range(runs + 1):  # the first round warms the disk cache and is dropped
        for name, argv in argvs.items():
            measured = timed_process(argv)
            if k:
                times[name].append(measured)
    out: dict = {}
    for name, pairs in times.items():
        out[name] = {
            "wall_s": median([w for w, _ in pairs]),
            "cpu_s": median([c for _, c in pairs]),
        }
        if name in MODES:
            out[name]["command"] = " ".join(
                ["python -m fretbem.app.cli demo", *MODES[name], "--out DIR"]
            )
            out[name]["target_wall_s"] = TARGETS[name]
            floor = times["floor_numpy_scipy_linalg"]
            out[name]["cpu_over_floor"] = median(
                [c / f[1] for (_, c), f in zip(pairs, floor, strict=True)]
            )
            out[name]["cpu_over_floor_runs"] = [
                round(c / f[1], 2) for (_, c), f in zip(pairs, floor, strict=True)
            ]
    return out


def phases(runs: int, directory: Path) -> dict:
    """Median of each phase (wall and CPU seconds) over ``runs`` fresh processes per mode,
    interleaved."""
    records: dict[str, list[dict]] = {mode: [] for mode in MODES}
    for _ in range(runs):
        for mode, flags in MODES.items():
            start = time.time()
            text = subprocess.run(
                [sys.executable, "-c", PHASES_CHILD, str(directory / f"p_{mode}"), *flags],
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            stop = time.time()
            record = json.loads(text.strip().splitlines()[-1])
            # interpreter start (to the child's first line) and exit (after its last line)
            record["start_up_wall"] = record.pop("begin") - start
            record["exit_wall"] = stop - record.pop("end")
            record["process_wall"] = stop - start
            records[mode].append(record)
    return {
        mode: {key: median([r.get(key, 0.0) for r in rows]) for key in sorted(rows[0])}
        for mode, rows in records.items()
    }


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--runs", type=int, default=7, help="fresh processes per timing (>= 5)")
    parser.add_argument("--json", help="also write the JSON document here")
    args = parser.parse_args(argv)
    report: dict = {"cores": os.cpu_count(), "load_before": load()}
    with tempfile.TemporaryDirectory() as tmp:
        report["whole_process"] = whole_process(args.runs, Path(tmp))
        report["phases"] = phases(args.runs, Path(tmp))
    report["load_after"] = load()
    text = json.dumps(report, indent=2)
    print(text)
    if args.json:
        Path(args.json).write_text(text + "\n")
    return report


if __name__ == "__main__":
    main()
