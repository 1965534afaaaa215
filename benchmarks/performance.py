"""The performance budget of issue 4: cycle, demo process, assembly scaling, steps, memory.

Every timing is the median of ``--runs`` (>= 5) runs after one warm-up; the machine's core
count, platform and BLAS thread setting are printed first. Benchmarks:

- ``cycle``: the reference five-step cycle at 61 pairs, in-process, from building the scene
  (assembly included) to the last step; target <= 0.5 s on 2 cores;
- ``demo``: ``fretbem demo --no-figures --no-vtk`` (and ``--no-figures`` with VTK) as a whole
  process; target <= 3 s; also checks that importing fretbem imports neither matplotlib
  nor pyvista;
- ``assembly``: H and G of one body (the scene's pad with every element count scaled)
  against its degrees of freedom, about 200 to 8000, with the fitted exponent;
- ``steps``: the per-step solve time (five steps on the condensed problem) against pairs;
- ``memory``: tracemalloc peak of the largest study case (lagrange2, 481 pairs) and of the
  largest assembly.

Run from the repository root::

    python benchmarks/performance.py --json bench.json
    python benchmarks/performance.py --only cycle --profile        # cProfile of the cycle
    OPENBLAS_NUM_THREADS=1 python benchmarks/performance.py --only cycle steps
"""

from __future__ import annotations

import argparse
import cProfile
import gc
import io
import json
import math
import os
import platform
import pstats
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import ContactState, run

TARGETS = {"cycle": 0.5, "demo": 3.0}
HEAVY = ("matplotlib", "pyvista", "vtk", "vtkmodules")


def machine() -> dict:
    threads = {
        k: os.environ[k]
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
        if k in os.environ
    }
    return {
        "cores": os.cpu_count(),
        "processor": platform.processor() or platform.machine(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "blas_threads_env": threads or "default (OpenBLAS: one thread per core)",
        "load_average_1min": os.getloadavg()[0],
    }


def timed(function, runs: int, warmup: int = 1) -> list[float]:
    for _ in range(warmup):
        function()
    times = []
    for _ in range(runs):
        gc.collect()
        tic = time.perf_counter()
        function()
        times.append(time.perf_counter() - tic)
    return times


def fit(x, y) -> float:
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def describe(times: list[float]) -> str:
    return (
        f"median {statistics.median(times):.3f} s (min {min(times):.3f}, max {max(times):.3f}, "
        f"{len(times)} runs)"
    )


# -- benchmarks -----------------------------------------------------------------------------
def bench_cycle(args, report) -> None:
    """The five-step cycle at 61 pairs, scene construction and assembly included."""
    parts = []

    def once():
        result = run(cattaneo_mindlin(basis=args.basis, pairs=61))
        parts.append(result.timings)

    first = time.perf_counter()
    once()  # the warm-up: first-call costs (quadrature rules, plugin discovery)
    first = time.perf_counter() - first
    parts.clear()
    times = timed(once, args.runs, warmup=0)
    breakdown = {k: statistics.median(p[k] for p in parts) for k in parts[0]}
    print(f"cycle, {args.basis}, 61 pairs: {describe(times)}; first run {first:.3f} s")
    print("  medians: " + ", ".join(f"{k} {v:.3f} s" for k, v in breakdown.items()))
    report(
        "cycle",
        f"five-step cycle, 61 pairs, {args.basis}, in-process",
        times,
        target=TARGETS["cycle"],
        breakdown=breakdown,
        first_run=first,
    )
    if args.profile:
        profile(lambda: run(cattaneo_mindlin(basis=args.basis, pairs=61)), "the cycle")


def _command() -> list[str]:
    script = shutil.which("fretbem")
    return [script] if script else [sys.executable, "-m", "fretbem.app.cli"]


def bench_demo(args, report) -> None:
    """``fretbem demo`` as a whole process, figures off, with and without VTK."""
    code = (
        "import sys, fretbem, fretbem.app.cli, fretbem.scenes, fretbem.simulation, fretbem.results;"
        f"print([m for m in {HEAVY!r} if m in sys.modules])"
    )
    heavy = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.strip()
    print(f"heavy modules imported by `import fretbem` and the demo's modules: {heavy}")
    importtime = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", "import fretbem.app.cli, fretbem.scenes"],
        capture_output=True,
        text=True,
        check=True,
    ).stderr
    top = sorted(
        (
            (int(line.split("|")[1]), line.split("|")[2].strip())
            for line in importtime.splitlines()
            if line.startswith("import time:") and line.split("|")[1].strip().isdigit()
        ),
        reverse=True,
    )[:6]
    print("  largest cumulative imports (us): " + ", ".join(f"{n} {t}" for t, n in top))
    with tempfile.TemporaryDirectory() as tmp:
        for name, flags in (
            ("demo", ["--no-figures", "--no-vtk"]),
            ("demo_vtk", ["--no-figures"]),
        ):
            command = [*_command(), "demo", *flags, "--out", tmp]

            def once(command=command):
                subprocess.run(command, check=True, capture_output=True)

            times = timed(once, args.runs)
            print(f"`fretbem demo {' '.join(flags)}` (whole process): {describe(times)}")
            report(
                name,
                f"fretbem demo {' '.join(flags)}, whole process",
                times,
                target=TARGETS["demo"],
                heavy_imports=heavy,
            )
    interpreter = timed(
        lambda: subprocess.run([sys.executable, "-c", "pass"], check=True), args.runs
    )
    imports = timed(
        lambda: subprocess.run(
            [sys.executable, "-c", "import fretbem.app.cli, fretbem.scenes, fretbem.simulation"],
            check=True,
        ),
        args.runs,
    )
    print(
        f"  bare interpreter {statistics.median(interpreter):.3f} s, interpreter + fretbem "
        f"imports {statistics.median(imports):.3f} s"
    )
    report("python_startup", "bare python interpreter start", interpreter)
    report("fretbem_import", "python start + import fretbem.app.cli/scenes/simulation", imports)


def scaled_body(k: float, basis: str = "nurbs"):
    """The scene's pad with the contact zone and every other element count scaled by k."""
    sim = cattaneo_mindlin(
        basis=basis,
        pairs=int(14 * k) + 1,
        flank_elements=max(1, round(16 * k)),
        side_elements=max(1, round(12 * k)),
        top_elements=max(1, round(12 * k)),
    )
    return sim.pair.upper


def bench_assembly(args, report) -> None:
    """Assembly time of one body against its DOFs, with the fitted exponent."""
    scales = [k for k in (1, 2, 4, 8, 16, 24, 32, 48) if 170 * k <= args.max_dofs]
    dofs, medians, rows = [], [], []
    print(f"assembly of one body ({args.basis}, the pad with all element counts scaled):")
    print("   scale   DOFs   median s    min s    max s   runs")
    for k in scales:
        runs = args.runs if 170 * k <= 3000 else max(args.large_runs, 1)

        def once(k=k):
            scaled_body(k, args.basis).matrices()

        times = timed(once, runs, warmup=1 if k < 16 else 0)
        n = scaled_body(k, args.basis).dofs
        dofs.append(n)
        medians.append(statistics.median(times))
        rows.append({"scale": k, "dofs": n, "times": times})
        print(
            f"  {k:6g} {n:6d} {medians[-1]:10.3f} {min(times):8.3f} {max(times):8.3f} "
            f"{len(times):6d}",
            flush=True,
        )
    exponent = fit(dofs, medians)
    upper = fit(dofs[len(dofs) // 2 :], medians[len(medians) // 2 :])
    print(f"  fitted exponent: time ~ DOFs^{exponent:.2f} (all), ^{upper:.2f} (upper half)")
    report(
        "assembly_largest",
        f"assembly of one body, {dofs[-1]} DOFs",
        rows[-1]["times"],
        series=rows,
        exponent=exponent,
        exponent_upper_half=upper,
    )
    if args.profile:
        k = scales[min(len(scales) - 1, 4)]
        profile(lambda: scaled_body(k, args.basis).matrices(), f"assembly at scale {k}")


def bench_steps(args, report) -> None:
    """Five steps on a condensed problem (prepared once), against pairs."""
    print(f"per-step solve ({args.basis}; condensed once, five steps timed together):")
    print("   pairs  iterations  median s/step   min      max")
    pairs_list, per_step, rows = [], [], []
    for pairs in (15, 31, 61, 121, 241, 481):
        sim = cattaneo_mindlin(basis=args.basis, pairs=pairs)
        problem = sim.prepare()
        counts = []

        def cycle(sim=sim, problem=problem, counts=counts):
            state, total = ContactState.initial(problem), 0
            for load in sim.steps:
                state, iterations, _ = sim.step(problem, state, load)
                total += iterations
            counts.append(total)

        times = [t / len(sim.steps) for t in timed(cycle, args.runs)]
        pairs_list.append(pairs)
        per_step.append(statistics.median(times))
        rows.append({"pairs": pairs, "iterations": counts[-1], "times": times})
        print(
            f"  {pairs:6d} {counts[-1]:11d} {per_step[-1]:14.5f} {min(times):8.5f} "
            f"{max(times):8.5f}",
            flush=True,
        )
    exponent = fit(pairs_list, per_step)
    print(f"  fitted exponent: per-step time ~ pairs^{exponent:.2f}")
    report(
        "step_481",
        f"one load step, {args.basis}, 481 pairs",
        rows[-1]["times"],
        series=rows,
        exponent=exponent,
    )


MEMORY_PROBE = """
import resource, sys, tracemalloc
sys.path.insert(0, {here!r})
from performance import scaled_body
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run

def high_water():  # MiB; VmHWM (Linux) is reset by exec, unlike ru_maxrss
    try:
        with open("/proc/self/status") as status:
            line = next(x for x in status if x.startswith("VmHWM:"))
        return int(line.split()[1]) / 1024
    except (OSError, StopIteration):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

before = high_water()
tracemalloc.start()
{call}
peak = tracemalloc.get_traced_memory()[1]
tracemalloc.stop()
after = high_water()
print(peak / 2**20, after, after - before)
"""


def bench_memory(args, report) -> None:
    """Peak memory of the largest study case and of the largest assembly, each in a fresh
    process: the tracemalloc peak (Python and numpy allocations) and the growth of the
    process's resident-set high-water mark (VmHWM) over the imports."""
    largest = max(k for k in (1, 2, 4, 8, 16, 24, 32, 48) if 170 * k <= args.max_dofs)
    cases = [
        ("cycle_481_lagrange2", "run(cattaneo_mindlin(basis='lagrange2', pairs=481))"),
        ("cycle_481_nurbs4", "run(cattaneo_mindlin(basis='nurbs', degree=4, pairs=481))"),
        (f"assembly_{largest}", f"scaled_body({largest}, {args.basis!r}).matrices()"),
    ]
    here = os.path.dirname(os.path.abspath(__file__))
    for name, call in cases:
        code = MEMORY_PROBE.format(here=here, call=call)
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        ).stdout.split()
        peak, rss, growth = map(float, out[-3:])
        print(
            f"peak memory, {name}: tracemalloc {peak:.0f} MiB; process max RSS {rss:.0f} MiB, "
            f"{growth:.0f} MiB above the imports"
        )
        report(f"memory_{name}", f"peak memory (tracemalloc), {name}", [peak], unit="MiB")
        report(f"rss_{name}", f"max RSS growth over imports, {name}", [growth], unit="MiB")


def profile(function, label: str) -> None:
    """Top of a cProfile run (cumulative and own time)."""
    profiler = cProfile.Profile()
    profiler.enable()
    function()
    profiler.disable()
    for key in ("cumulative", "tottime"):
        stream = io.StringIO()
        pstats.Stats(profiler, stream=stream).sort_stats(key).print_stats(18)
        print(f"--- cProfile of {label}, by {key} ---")
        print("\n".join(stream.getvalue().splitlines()[4:]))


BENCHMARKS = {
    "cycle": bench_cycle,
    "demo": bench_demo,
    "assembly": bench_assembly,
    "steps": bench_steps,
    "memory": bench_memory,
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", choices=list(BENCHMARKS), default=list(BENCHMARKS))
    parser.add_argument("--runs", type=int, default=5, help="timed runs per benchmark (>= 5)")
    parser.add_argument(
        "--large-runs", type=int, default=5, help="timed runs of assemblies above 3000 DOFs"
    )
    parser.add_argument("--max-dofs", type=int, default=8200, help="largest assembly size")
    parser.add_argument("--basis", default="nurbs")
    parser.add_argument("--profile", action="store_true", help="cProfile the cycle/assembly")
    parser.add_argument("--json", help="write the medians and series to this JSON file")
    args = parser.parse_args(argv)
    info = machine()
    print(
        f"{info['cores']} cores, {info['processor']}, {info['platform']}, python "
        f"{info['python']}, numpy {info['numpy']}, BLAS threads: {info['blas_threads_env']}, "
        f"load average {info['load_average_1min']:.2f}"
    )
    results = []

    def report(name, label, values, *, target=None, unit="s", **extra):
        results.append(
            {
                "name": label,
                "key": name,
                "median": statistics.median(values),
                "runs": values,
                "target": target,
                "unit": unit,
                **extra,
            }
        )

    for name in args.only:
        BENCHMARKS[name](args, report)
    print("\nsummary:")
    for item in results:
        target = item["target"]
        verdict = "" if target is None else ("  met" if item["median"] <= target else "  MISSED")
        limit = "" if target is None else f" (target <= {target:g} {item['unit']})"
        print(f"  {item['name']}: {item['median']:.3f} {item['unit']}{limit}{verdict}")
    if args.json:
        info["load_average_1min_end"] = os.getloadavg()[0]
        with open(args.json, "w") as handle:
            json.dump({"machine": info, "results": results}, handle, indent=2, default=float)
    return 0 if all(math.isfinite(r["median"]) for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
