"""Whole-process time of ``fretbem demo`` with and without figures and VTK (issue 16).

Each timing is one fresh process (``fretbem demo ... --out DIR``, the console script beside
``sys.executable``, not a pyenv shim); the modes are interleaved and the median of ``--runs``
is printed with the load average before and after. A per-phase breakdown comes from fresh
processes that run ``fretbem.app.cli.main`` with timers around the run, the figures and the VTK
writer; floors (bare interpreter, numpy, scipy.linalg) bound what the demo can reach.
Prints one JSON document. Usage::

    python benchmarks/demo_process.py --runs 7 [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
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
import json, sys
start = time.perf_counter()
import fretbem.app.cli, fretbem.app.commands  # the options, then the demo's code
import_cli = time.perf_counter() - start
start = time.perf_counter()
import fretbem.output, fretbem.scenes, fretbem.simulation
import_run = time.perf_counter() - start
start = time.perf_counter()
import fretbem.output.figures
import_plot = time.perf_counter() - start
start = time.perf_counter()
import fretbem.output.vtk
import_vtk = time.perf_counter() - start
spent = {"solve": 0.0, "figures": 0.0, "vtk": 0.0}

def timed(module, name, phase):
    inner = getattr(module, name)
    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            spent[phase] += time.perf_counter() - start
    setattr(module, name, wrapper)

timed(fretbem.simulation, "run", "solve")
timed(fretbem.output.figures, "save_figures", "figures")
timed(fretbem.output.vtk, "save_vtk", "vtk")
start = time.perf_counter()
code = fretbem.app.cli.main(["demo", *sys.argv[2:], "--out", sys.argv[1]])
main = time.perf_counter() - start
assert code == 0, code
print(json.dumps({
    "import_cli": import_cli, "import_run": import_run, "import_plot": import_plot,
    "import_vtk": import_vtk, **spent,
    "other": main - sum(spent.values()), "main": main, "begin": begin, "end": time.time(),
}), flush=True)
"""


def command() -> list[str]:
    """The installed console script beside this interpreter (a shim would add ~0.08 s)."""
    script = Path(sys.executable).with_name("fretbem")
    if script.is_file():
        return [str(script)]
    return [sys.executable, "-c", "import sys; from fretbem.app.cli import main; sys.exit(main())"]


def wall(argv: list[str]) -> float:
    """Wall time of one fresh process (its output discarded; a failure raises)."""
    start = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True)
    return time.perf_counter() - start


def load() -> list[float]:
    return [round(v, 2) for v in os.getloadavg()]


def median(values: list[float]) -> float:
    return round(statistics.median(values), 3)


def whole_process(runs: int, directory: Path) -> dict:
    """Median wall time per mode over ``runs`` interleaved fresh processes."""
    times: dict[str, list[float]] = {mode: [] for mode in MODES}
    for k in range(runs + 1):  # the first round warms the disk cache and is dropped
        for mode, flags in MODES.items():
            seconds = wall([*command(), "demo", *flags, "--out", str(directory / mode)])
            if k:
                times[mode].append(seconds)
    return {
        mode: {
            "command": f"fretbem demo {' '.join(MODES[mode])} --out DIR".replace("  ", " "),
            "median_s": median(t),
            "runs_s": [round(v, 3) for v in t],
            "target_s": TARGETS[mode],
            "met": statistics.median(t) <= TARGETS[mode],
        }
        for mode, t in times.items()
    }


def phases(runs: int, directory: Path) -> dict:
    """Median of each phase (seconds) over ``runs`` fresh processes per mode."""
    out = {}
    for mode, flags in MODES.items():
        records = []
        for _ in range(runs):
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
            record["start_up"] = record.pop("begin") - start
            record["exit"] = stop - record.pop("end")
            record["process"] = stop - start
            records.append(record)
        out[mode] = {key: median([r[key] for r in records]) for key in records[0]}
    return out


def floors(runs: int) -> dict:
    """Median wall time of a fresh interpreter doing only the given imports."""
    return {
        name: median([wall([sys.executable, "-c", code]) for _ in range(runs)])
        for name, code in FLOORS.items()
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
    report["floors"] = floors(args.runs)
    report["load_after"] = load()
    text = json.dumps(report, indent=2)
    print(text)
    if args.json:
        Path(args.json).write_text(text + "\n")
    return report


if __name__ == "__main__":
    main()
