"""Sweep speed: per-case cost against the assembly, a 1,000-case load sweep, a size-effect sweep.

    python benchmarks/sweep_benchmark.py [--cases 1000] [--radii 20] [--workers N] [--json F]

The issue-28 targets of the sweep engines, whole processes of ``fretbem sweep`` (CPU of the
process and its workers, and wall), before and after alternating round by round::

    git archive <old commit> | tar -x -C /tmp/before
    OPENBLAS_NUM_THREADS=1 python benchmarks/sweep_benchmark.py --targets \
        --before /tmp/before --rounds 3 --json docs/results/sweeps.json
    python benchmarks/performance_page.py

``--sharing [PAIRS ...]`` (see ``sharing``): a prepared group pickled and unpickled for a
Dask worker against that worker assembling it again (forked workers inherit it).

``--targets`` (see ``targets``): the example map (144 cases) default engine against
``--serial``; the same map with 10x its work (1,440 cases) default against ``--serial``;
a 10,000-case load sweep at 61 pairs with the default engine. The trees' bytecode is
written first (as ``workflows.py`` does: this machine sets PYTHONDONTWRITEBYTECODE, and
every process would compile fretbem again), the two engines alternate which runs first, and
the ratios are medians of per-round ratios. Each process reports its own CPU and its
workers': on a loaded machine two workers do not get two cores, so besides the wall
speed-up the table gives the speed-up on two free cores from the CPU times (the sweep's
process alone before and after its workers, half its workers' and its own while they ran,
``two_free_cores``).

1. Reuse: on the reference scene (61 pairs) the assembly + condensation of one geometry
   against the solve of one load case on it, and a case built and solved from scratch.
2. Load sweep: P x Q amplitude (a fully reversed cycle, every case below gross slip) on one
   geometry, with the default LocalCluster (one process per core) and serially; compared
   with the ideal wall time (serial per-case time x cases / cores + one assembly).
3. Size effect: ``--radii`` pad radii (one assembly each), serially and on the cluster.

Timings are medians over ``--repeat`` runs where it says so; the machine may be shared.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

from workflows import compile_tree  # the trees' bytecode, as the workflow runs have it

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
CYCLE = [0.0, 1.0, 0.0, -1.0, 0.0]


def reference_scene() -> dict:
    return tomllib.loads((ROOT / "examples" / "cattaneo_mindlin.toml").read_text())


def reuse(repeat: int) -> dict:
    """Assembly + condensation of one group vs one case on it vs one case from scratch."""
    from fretbem.simulation import run
    from fretbem.studies.sweep import cases as sweep_cases
    from fretbem.studies.sweep.spec import SweepSpec

    scene = reference_scene()
    spec = SweepSpec.from_mapping(
        scene, {"load.Q": {"start": 2.0, "stop": 26.0, "num": 25, "pattern": CYCLE}}
    )
    cases = spec.cases()
    rep = sweep_cases.representative([c.scene for c in cases])
    assembly, per_case = [], []
    for _ in range(repeat):
        sweep_cases._GROUPS.clear()
        tic = time.perf_counter()
        rows = sweep_cases.run_batch(rep, [(c.index, c.values, c.scene) for c in cases])
        total = time.perf_counter() - tic
        assembly.append(rows[0]["assembly_seconds"])
        per_case.append((total - rows[0]["assembly_seconds"]) / len(cases))
    scratch = []
    for case in cases[:repeat]:
        tic = time.perf_counter()
        run(sweep_cases.build_simulation(case.scene))
        scratch.append(time.perf_counter() - tic)
    out = {
        "assembly_condensation_s": statistics.median(assembly),
        "per_case_reused_s": statistics.median(per_case),
        "per_case_from_scratch_s": statistics.median(scratch),
    }
    out["assembly_over_case"] = out["assembly_condensation_s"] / out["per_case_reused_s"]
    out["reuse_speedup"] = out["per_case_from_scratch_s"] / out["per_case_reused_s"]
    return out


def _timed_sweep(parameters, workers, serial, **kw) -> tuple[float, object]:
    from fretbem.studies.sweep.run import sweep

    with tempfile.TemporaryDirectory() as tmp:
        tic = time.perf_counter()
        result = sweep(
            reference_scene(),
            parameters,
            out=Path(tmp) / "s",
            serial=serial,
            workers=workers,
            progress=False,
            **kw,
        )
        return time.perf_counter() - tic, result


def load_sweep(cases: int, workers: int, per_case: float, assembly: float) -> dict:
    """P x Q on one geometry: LocalCluster (incl. its start) and serial, against the ideal."""
    from fretbem.studies.sweep import cases as sweep_cases

    n_p = 10
    n_q = max(1, cases // n_p)
    parameters = {
        "load.P": {"start": 60.0, "stop": 140.0, "num": n_p},
        # below gross slip everywhere: |Q| <= 0.95 f P_min
        "load.Q": {"start": 0.0, "stop": 0.95 * 0.3 * 60.0, "num": n_q, "pattern": CYCLE},
    }
    sweep_cases._GROUPS.clear()
    dask_wall, result = _timed_sweep(parameters, workers, serial=False)
    solved = int((result.table["status"] == "ok").sum())
    sweep_cases._GROUPS.clear()
    serial_wall, serial_result = _timed_sweep(parameters, None, serial=True)
    n = n_p * n_q
    serial_case = (serial_wall - assembly) / n
    ideal = serial_case * n / workers + assembly
    cpu = {
        "dask_cpu_per_case_s": float(result.table["solve_cpu_seconds"].median()),
        "serial_cpu_per_case_s": float(serial_result.table["solve_cpu_seconds"].median()),
        "dask_wall_per_case_s": float(result.table["solve_seconds"].median()),
        "serial_wall_per_case_s": float(serial_result.table["solve_seconds"].median()),
    }
    return {
        **cpu,
        "cases": n,
        "solved": solved,
        "workers": workers,
        "dask_wall_s": dask_wall,
        "serial_wall_s": serial_wall,
        "serial_per_case_s": serial_case,
        "ideal_s": ideal,
        "dask_over_ideal": dask_wall / ideal,
        "dask_speedup_over_serial": serial_wall / dask_wall,
        "summary": str(result.summary),
        "serial_summary": str(serial_result.summary),
        "reuse_per_case_s": per_case,
    }


def size_effect(radii: int, workers: int) -> dict:
    """``radii`` pad radii, one assembly each, one load case per radius."""
    from fretbem.studies.sweep import cases as sweep_cases

    parameters = {
        "geometry.radius": {"start": 30.0, "stop": 120.0, "num": radii},
        "load.Q": {"values": [12.0], "pattern": CYCLE},
    }
    sweep_cases._GROUPS.clear()
    serial_wall, _ = _timed_sweep(parameters, None, serial=True)
    dask_wall, result = _timed_sweep(parameters, workers, serial=False)
    return {
        "radii": radii,
        "workers": workers,
        "serial_wall_s": serial_wall,
        "dask_wall_s": dask_wall,
        "speedup": serial_wall / dask_wall,
        "summary": str(result.summary),
    }


def sharing(pairs: Sequence[int], repeat: int) -> dict:
    """A prepared group sent to a worker against the worker assembling it again, per pair
    count: build + prepare (assembly and condensation) against pickling the prepared
    simulation and unpickling it (what a Dask worker receives; a forked worker inherits
    it for nothing), with the pickle's size. Medians of ``repeat`` runs."""
    import pickle

    from fretbem.studies.sweep.cases import build_simulation

    out = {}
    for n in pairs:
        scene = reference_scene()
        scene["contact"]["pairs"] = n
        build, dumps, loads, size = [], [], [], 0
        for _ in range(repeat):
            tic = time.perf_counter()
            simulation = build_simulation(scene)
            simulation.prepare()
            build.append(time.perf_counter() - tic)
            tic = time.perf_counter()
            data = pickle.dumps(simulation, protocol=pickle.HIGHEST_PROTOCOL)
            dumps.append(time.perf_counter() - tic)
            tic = time.perf_counter()
            pickle.loads(data)
            loads.append(time.perf_counter() - tic)
            size = len(data)
        ship = statistics.median(dumps) + statistics.median(loads)
        out[n] = {
            "assembly_condensation_s": statistics.median(build),
            "pickle_s": statistics.median(dumps),
            "unpickle_s": statistics.median(loads),
            "pickle_MB": size / 1e6,
            "assembly_over_shipping": statistics.median(build) / ship,
        }
        print(f"{n} pairs: " + ", ".join(f"{k} {v:.3g}" for k, v in out[n].items()), flush=True)
    return out


def cluster_start(workers: int) -> float:
    """Seconds to start and stop the default LocalCluster (part of every Dask run above)."""
    from dask.distributed import Client

    from fretbem.studies.sweep.run import _local_cluster

    tic = time.perf_counter()
    with _local_cluster(workers) as cluster, Client(cluster) as client:
        client.submit(sum, [1, 2]).result()
    return time.perf_counter() - tic


def _sweep_file(folder: Path, name: str, parameters: str, outputs: bool) -> Path:
    """A sweep file on the reference scene (absolute path) with ``parameters`` (TOML)."""
    scene = (ROOT / "examples" / "cattaneo_mindlin.toml").as_posix()
    extra = 'outputs = ["fretbem.studies.sweep.outputs:surface_stress"]\n' if outputs else ""
    path = folder / f"{name}.toml"
    path.write_text(f'[sweep]\nscene = "{scene}"\nmode = "product"\n{extra}[parameters]\n'
                    + parameters)  # fmt: skip
    return path


#: the target sweeps: (name, [parameters] table, extra output column)
TARGET_SWEEPS = (
    # the example's map (examples/fretting_map.toml)
    ("map144", '"load.P" = { start = 60.0, stop = 140.0, num = 12 }\n'
     '"load.Q" = { start = 0.0, stop = 44.0, num = 12, pattern = [0.0, 1.0, 0.0, -1.0, 0.0] }\n',
     True),
    # the same map with ten times the Q values: 10x the work
    ("map1440", '"load.P" = { start = 60.0, stop = 140.0, num = 12 }\n'
     '"load.Q" = { start = 0.0, stop = 44.0, num = 120, pattern = [0.0, 1.0, 0.0, -1.0, 0.0] }\n',
     True),
    # 10,000 load cases below gross slip (|Q| <= 0.95 f P_min)
    ("load10k", '"load.P" = { start = 60.0, stop = 140.0, num = 10 }\n'
     '"load.Q" = { start = 0.0, stop = 17.1, num = 1000, pattern = [0.0, 1.0, 0.0, -1.0, 0.0] }\n',
     False),
)  # fmt: skip


#: a ``fretbem sweep`` process that reports its own CPU, its workers' (RUSAGE_CHILDREN: the
#: forked workers it has waited for) and its own while its forked workers ran (``_run_pool``)
#: on its last line of stderr. It calls the console script's ``main()`` (arguments from
#: sys.argv), so it ends as ``fretbem sweep`` does: main(argv) would leave the interpreter's
#: teardown to pass the collector over every object (0.35-0.4 CPU s a process, both engines)
SWEEP_CHILD = r"""
import json, resource, sys, time
import fretbem.studies.sweep.run as engine
from fretbem.app.cli import main
pool = [0.0, 0.0]
run_pool = getattr(engine, "_run_pool", None)
if run_pool is not None:
    def timed_pool(*args, **kwargs):
        pool[0] = time.process_time()
        try:
            return run_pool(*args, **kwargs)
        finally:
            pool[1] = time.process_time()
    engine._run_pool = timed_pool
sys.argv = ["fretbem", "sweep", *sys.argv[1:]]
try:
    code = main()  # as the console script runs it: its process ends as `fretbem sweep` does
finally:
    own = resource.getrusage(resource.RUSAGE_SELF)
    workers = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = [own.ru_utime + own.ru_stime, workers.ru_utime + workers.ru_stime, pool[1] - pool[0]]
    sys.stderr.write("\nCPU " + json.dumps(cpu) + "\n")
raise SystemExit(code)
"""


def _sweep_process(tree: Path, sweep_file: Path, out: Path, *flags: str) -> dict[str, float]:
    """Wall and CPU (the whole process tree; the sweep's own process; its workers; its own
    while its forked workers ran) of one ``fretbem sweep`` process."""
    import resource
    import shutil
    import subprocess

    shutil.rmtree(out, ignore_errors=True)
    env = {**os.environ, "PYTHONPATH": f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}",
           "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}  # fmt: skip
    command = [sys.executable, "-c", SWEEP_CHILD, str(sweep_file), "--out", str(out),
               "--no-figures", "--quiet", *flags]  # fmt: skip
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    tic = time.perf_counter()
    done = subprocess.run(command, env=env, cwd=out.parent, capture_output=True, text=True)
    wall = time.perf_counter() - tic
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    own, workers, pool = json.loads(done.stderr.strip().splitlines()[-1].removeprefix("CPU "))
    return {"wall": wall, "cpu": cpu, "own_cpu": own, "workers_cpu": workers, "pool_cpu": pool}


def two_free_cores(run: dict[str, float], workers: int = 2) -> float:
    """The wall time of a run on ``workers`` free cores, from its CPU times: the sweep's own
    process in full before its workers start and after they stop (its start, the cases
    before forking, the table, its exit: the whole process tree's CPU less what the process
    reported and its workers'), and its workers' CPU with its own meanwhile (storing their
    rows) shared by the cores, as if balanced. A loaded machine stretches wall times, not
    these (nor does it give a sweep's processes more of the cores than one process: the
    kernel shares them between sessions, /proc/sys/kernel/sched_autogroup_enabled)."""
    pool = run.get("pool_cpu", 0.0)
    exit_cpu = max(0.0, run["cpu"] - run["own_cpu"] - run["workers_cpu"])
    return run["own_cpu"] - pool + exit_cpu + (pool + run["workers_cpu"]) / workers


def targets(trees: dict[str, Path], rounds: int, work: Path, big: bool = True) -> dict:
    """Medians over ``rounds`` interleaved rounds of every target sweep, per tree; the
    default engine and ``--serial`` alternate which runs first from round to round."""
    files = {name: _sweep_file(work, name, table, outputs)
             for name, table, outputs in TARGET_SWEEPS}  # fmt: skip
    runs: dict[str, list[dict]] = {label: [] for label in trees}
    for tree in trees.values():  # unmeasured: bytecode and numba caches of a fresh tree
        _sweep_process(tree, files["map144"], work / "warm-up", "--serial")
    engines = (("default", ()), ("serial", ("--serial",)))
    for k in range(rounds):
        for label, tree in trees.items():
            one = {}
            for name in ("map144", "map1440"):
                for engine, flags in engines[:: 1 if k % 2 == 0 else -1]:
                    run = _sweep_process(tree, files[name], work / f"{name}-{engine}", *flags)
                    for key, value in run.items():
                        one[f"{name}_{engine}_{key}"] = value
            if big:
                run = _sweep_process(tree, files["load10k"], work / "load10k")
                for key, value in run.items():
                    one[f"load10k_default_{key}"] = value
            runs[label].append(one)
            shown = {n: v for n, v in one.items() if n.endswith(("_wall", "_cpu"))
                     and not any(w in n for w in ("own", "workers", "pool"))}  # fmt: skip
            print(f"round {k + 1} {label}: " + ", ".join(f"{n} {v:.1f}" for n, v in shown.items()),
                  f"(load {os.getloadavg()[0]:.1f})", flush=True)  # fmt: skip
    medians = {label: {n: statistics.median(r[n] for r in rs) for n in rs[0]}
               for label, rs in runs.items()}  # fmt: skip
    ratios = {}
    for label, rs in runs.items():
        m = medians[label]
        # per round, then the median: the two runs of a round saw the same load
        per_round = {
            "wall144": [r["map144_default_wall"] / r["map144_serial_wall"] for r in rs],
            "cpu144": [r["map144_default_cpu"] / r["map144_serial_cpu"] for r in rs],
            "wall1440": [r["map1440_serial_wall"] / r["map1440_default_wall"] for r in rs],
            "free1440": [
                r["map1440_serial_cpu"] / two_free_cores(_run(r, "map1440_default")) for r in rs
            ],
        }
        per_round = {n: statistics.median(v) for n, v in per_round.items()}
        ratios[label] = {
            "sweep default / --serial, 144 cases (wall)": per_round["wall144"],
            "sweep default / --serial, 144 cases (CPU)": per_round["cpu144"],
            "sweep --serial / default, 1,440 cases (wall speed-up)": per_round["wall1440"],
            "sweep --serial CPU / default on two free cores, 1,440 cases (speed-up)": per_round[
                "free1440"
            ],
            "sweep default / --serial, 1,440 cases (CPU)": m["map1440_default_cpu"]
            / m["map1440_serial_cpu"],
        }
        if "load10k_default_wall" in m:
            ratios[label]["10,000-case load sweep, default engine (wall s)"] = m[
                "load10k_default_wall"
            ]
            ratios[label]["10,000-case load sweep, CPU s per case (ms)"] = (
                1000 * m["load10k_default_cpu"] / 10_000
            )
            ratios[label]["10,000-case load sweep on two free cores, from its CPU (wall s)"] = (
                statistics.median(two_free_cores(_run(r, "load10k_default")) for r in rs)
            )
    return {"medians": medians, "ratios": ratios}


def _run(one: dict, prefix: str) -> dict[str, float]:
    """The timings of one process of a round (``<prefix>_wall``, ``_own_cpu``...)."""
    keys = ("wall", "cpu", "own_cpu", "workers_cpu", "pool_cpu")
    return {key: one[f"{prefix}_{key}"] for key in keys}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--targets",
        action="store_true",
        help="the issue-28 engine targets, whole processes (see the docstring)",
    )
    parser.add_argument("--before", type=Path, help="with --targets: a tree of the old code")
    parser.add_argument(
        "--after", type=Path, default=ROOT, help="with --targets: the new code (this checkout)"
    )
    parser.add_argument("--rounds", type=int, default=3, help="with --targets")
    parser.add_argument("--no-10k", action="store_true", help="with --targets: skip the 10k sweep")
    parser.add_argument(
        "--source-only",
        action="store_true",
        help="with --targets: do not write the trees' bytecode first (every process compiles)",
    )
    parser.add_argument(
        "--sharing",
        nargs="*",
        type=int,
        metavar="PAIRS",
        help="only: a prepared group pickled for a worker against assembling it, per pair count",
    )
    parser.add_argument("--cases", type=int, default=1000)
    parser.add_argument("--radii", type=int, default=20)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.targets:
        trees = {"after": args.after.resolve()}
        if args.before:
            trees = {"before": args.before.resolve(), **trees}
        if not args.source_only:  # as an installed package has it (see workflows.py)
            for tree in trees.values():
                compile_tree(tree)
        load = [os.getloadavg()[0]]
        with tempfile.TemporaryDirectory() as tmp:
            report = targets(trees, args.rounds, Path(tmp), big=not args.no_10k)
        load.append(os.getloadavg()[0])
        report.update(machine=f"{os.cpu_count()} cores, {platform.platform()}, Python "
                      f"{platform.python_version()}", load=load, rounds=args.rounds)  # fmt: skip
        for name in report["ratios"]["after"]:
            cells = "".join(f"{report['ratios'][k].get(name, float('nan')):9.2f}" for k in trees)
            print(f"{name:58s}{cells}")
        if args.json:
            args.json.write_text(json.dumps(report, indent=1))
        return 0
    if args.sharing is not None:
        report = sharing(args.sharing or [61, 241, 481], args.repeat)
        if args.json:
            args.json.write_text(json.dumps(report, indent=1))
        return 0
    from fretbem.studies.sweep.run import machine_cores

    workers = args.workers or machine_cores()
    report = {
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}",
        "load_average_at_start": os.getloadavg(),
    }
    report["reuse"] = reuse(args.repeat)
    print(json.dumps(report["reuse"], indent=2))
    report["cluster_start_s"] = cluster_start(workers)
    print(f"LocalCluster start/stop with {workers} workers: {report['cluster_start_s']:.2f} s")
    report["load_sweep"] = load_sweep(
        args.cases,
        workers,
        report["reuse"]["per_case_reused_s"],
        report["reuse"]["assembly_condensation_s"],
    )
    load = report["load_sweep"]
    load["dask_minus_start_over_ideal"] = (load["dask_wall_s"] - report["cluster_start_s"]) / load[
        "ideal_s"
    ]
    print(json.dumps(load, indent=2))
    report["size_effect"] = size_effect(args.radii, workers)
    report["size_effect"]["speedup_without_start"] = report["size_effect"]["serial_wall_s"] / (
        report["size_effect"]["dask_wall_s"] - report["cluster_start_s"]
    )
    print(json.dumps(report["size_effect"], indent=2))
    report["load_average_at_end"] = os.getloadavg()
    print(f"load average at start {report['load_average_at_start']}, end {os.getloadavg()}")
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
