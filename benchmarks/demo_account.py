"""Where ``fretbem demo``'s CPU goes, piece by piece, against its import floor (issue 28 item 4).

Each run is a fresh process that runs the console script's demo (``fretbem.app.cli.main()``
with no argv, as installed; the cyclic collector off from the command's imports on, as
there) with CPU accumulators around the pieces that issue 28's limit is about: the imports
(numpy + scipy.linalg, fretbem, matplotlib), the attrs classes built during the run, the
registry's entry points, the solves (the numpy assembly, the LU and parameter solves), the
figures (axes and ticks made, text laid out and drawn, legends drawn, PNG encoding) and the
VTK files. A piece counts its outermost call only, but pieces overlap (text drawn inside a
legend is in both; attrs classes are built during the imports), so only the rows marked
``(all)`` and the imports add up. Beside every run, the floor ``python -c "import numpy,
scipy.linalg"`` (CPU of a fresh process) is measured; medians of ``--runs`` are printed with
each piece's share of the demo's CPU and its size in floors. The demo's limit is 4 floors.
``--before DIR`` runs a second source tree in the same rounds. Each tree's bytecode is written
first, as ``pip install`` leaves it (``workflows.compile_tree``; ``--source-only`` skips it,
and then every process compiles fretbem's modules again where PYTHONDONTWRITEBYTECODE is set,
~0.2 s CPU that the import row would show)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/demo_account.py --runs 5 [--before DIR] [--builtin]
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
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import time
import atexit, collections, json, sys
spent = collections.Counter()
active = set()

def timed(owner, name, label):
    inner = getattr(owner, name)
    def wrapper(*args, **kwargs):
        if label in active:
            return inner(*args, **kwargs)
        active.add(label)
        start = time.process_time()
        try:
            return inner(*args, **kwargs)
        finally:
            spent[label] += time.process_time() - start
            active.discard(label)
    setattr(owner, name, wrapper)

def imported(label, *names):
    start = time.process_time()
    for name in names:
        __import__(name)
    spent[label] += time.process_time() - start

imported("import numpy + scipy.linalg", "numpy", "scipy.linalg")
import attr._make
timed(attr._make._ClassBuilder, "build_class", "attrs classes built")
imported("import fretbem (cli, commands)", "fretbem.app.cli")
import gc
gc.disable()  # as main() does before it imports the command (UNCOLLECTED)
try:  # as main() does in the console script's process (a tree without it: nothing)
    from fretbem.app.lean_matplotlib import install
    install()
except ImportError:
    pass
imported("import fretbem (cli, commands)", "fretbem.app.commands")
imported("import matplotlib (figure, Agg)", "matplotlib.figure", "matplotlib.backends.backend_agg")
import matplotlib.axes._base, matplotlib.axis, matplotlib.legend, matplotlib.text
import matplotlib.backends.backend_agg as agg
import fretbem.app.cli, fretbem.bem.assembly, fretbem.bem.system, fretbem.output.figures
import fretbem.output.png, fretbem.output.vtk, fretbem.registry, fretbem.simulation
timed(fretbem.registry, "_installed_entry_points", "registry: entry points read")
timed(fretbem.bem.assembly, "assemble", "solves: assembly (numpy loops)")
timed(fretbem.bem.system, "_solve_parameters", "solves: LU and parameter solves")
timed(agg.RendererAgg, "draw_text", "figures: text drawn (glyphs)")
import fretbem.output.canvas
if "draw_text" in vars(fretbem.output.canvas._Renderer):  # the figures' canvas draws its own
    timed(fretbem.output.canvas._Renderer, "draw_text", "figures: text drawn (glyphs)")
timed(matplotlib.text.Text, "_get_layout", "figures: text laid out")
timed(matplotlib.legend.Legend, "draw", "figures: legends drawn")
timed(matplotlib.axes._base._AxesBase, "__init__", "figures: axes made")
timed(matplotlib.axis.Axis, "_get_tick", "figures: ticks made")
timed(fretbem.output.png, "png_bytes", "figures: PNG encoding")
timed(fretbem.output.vtk, "save_vtk", "VTK (all)")
run = fretbem.simulation.run
timed(fretbem.simulation, "run", "solves (all)")
for module in list(sys.modules.values()):  # the modules that imported run by name
    if getattr(module, "run", None) is run and module.__name__.startswith("fretbem"):
        module.run = fretbem.simulation.run
figures = fretbem.output.figures.save_figures
timed(fretbem.output.figures, "save_figures", "figures (all)")
for module in list(sys.modules.values()):
    if getattr(module, "save_figures", None) is figures and module.__name__.startswith("fretbem"):
        module.save_figures = fretbem.output.figures.save_figures
sys.argv = ["fretbem", "demo", "--out", sys.argv[1], *sys.argv[2:]]

def report():  # an exit handler: the console script's demo ends the process in main()
    spent["demo process (all)"] = time.process_time()
    print(json.dumps(spent), file=sys.__stderr__, flush=True)

atexit.register(report)
sys.stdout = open("/dev/null", "w")
fretbem.app.cli.main()
"""


#: the rows in the order printed
ORDER = (
    "import numpy + scipy.linalg", "import fretbem (cli, commands)",
    "import matplotlib (figure, Agg)", "attrs classes built", "registry: entry points read",
    "solves (all)", "solves: assembly (numpy loops)", "solves: LU and parameter solves",
    "figures (all)", "figures: axes made", "figures: ticks made", "figures: text laid out",
    "figures: text drawn (glyphs)", "figures: legends drawn", "figures: PNG encoding",
    "VTK (all)",
)  # fmt: skip


def _env(tree: Path) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
    env["OPENBLAS_NUM_THREADS"] = env["OMP_NUM_THREADS"] = "1"
    env["MPLBACKEND"] = "Agg"
    return env


def _floor(tree: Path) -> float:
    """CPU seconds of a fresh ``python -c "import numpy, scipy.linalg"``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-c", "import numpy, scipy.linalg"], env=_env(tree),
                   check=True)  # fmt: skip
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _demo(tree: Path, out: Path, flags: list[str]) -> dict:
    done = subprocess.run([sys.executable, "-c", CHILD, str(out), *flags], env=_env(tree),
                          capture_output=True, text=True, check=True)  # fmt: skip
    return json.loads(done.stderr.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--before", type=Path, help="source tree of the old code")
    parser.add_argument("--json", help="also write the medians here")
    parser.add_argument("--builtin", action="store_true",
                        help="compare the built-in families only (--compare lagrange2), what "
                        "`pip install . && fretbem demo` runs")  # fmt: skip
    parser.add_argument("--source-only", action="store_true",
                        help="do not write the trees' bytecode first")  # fmt: skip
    args = parser.parse_args(argv)
    trees = {"after": ROOT} if args.before is None else {"before": args.before, "after": ROOT}
    flags = ["--compare", "lagrange2"] if args.builtin else []
    if not args.source_only:
        from workflows import compile_tree  # this folder is first on the script's path

        for tree in trees.values():
            compile_tree(tree)
    rows: dict[str, list[dict]] = {name: [] for name in trees}
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.runs):
            for name, tree in trees.items():
                record = _demo(tree, Path(tmp) / f"{name}{k}", flags)
                record["floor"] = _floor(tree)
                rows[name].append(record)
            load.append(os.getloadavg()[0])
    out = {"load": [round(min(load), 2), round(max(load), 2)], "trees": {}}
    for name, records in rows.items():
        found = {key for r in records for key in r}
        keys = [key for key in ORDER if key in found] + sorted(found - set(ORDER))
        medians = {key: statistics.median(r.get(key, 0.0) for r in records) for key in keys}
        ratio = statistics.median(r["demo process (all)"] / r["floor"] for r in records)
        out["trees"][name] = {"cpu_s": medians, "demo_over_floor": ratio}
        total, floor = medians["demo process (all)"], medians["floor"]
        print(f"{name}: demo {total:.3f} s CPU, floor {floor:.3f} s, demo / floor {ratio:.2f} "
              f"(limit 4); load {out['load'][0]}-{out['load'][1]}")  # fmt: skip
        for key in keys:
            if key in ("floor", "demo process (all)"):
                continue
            value = medians[key]
            print(f"  {key:38s} {value:7.3f} s  {100 * value / total:5.1f} %  "
                  f"{value / floor:5.2f} floors")  # fmt: skip
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return out


if __name__ == "__main__":
    main()
