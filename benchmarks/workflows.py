"""The workflows the engineer waits for, each as a ratio against its floor or peer (issue 28).

Before and after in one run: ``--before DIR`` is a source tree of the old code (``git archive
<commit> | tar -x -C DIR``), the after tree is this checkout; every measurement runs in a
fresh process with ``PYTHONPATH`` set to the tree's ``framework`` and ``plugins`` and one BLAS
thread, the trees alternate round by round, and the medians of ``--rounds`` rounds are kept
(CPU seconds of the process and its children, and wall seconds; the machine is shared, so
ratios taken in the same round are what counts). Each tree's bytecode is written first, as an
installed package has it (``--source-only``: not, so every process compiles fretbem's modules
while numpy, scipy and matplotlib load their bytecode). Workflows:

- ``rig``: ``fretbem run examples/fretting_rig.toml`` (with [stress] and [fatigue]) against
  the same scene without those tables, whole process;
- ``fatigue``: the critical-plane search, all four criteria, on 10,000 points and a
  9-step cycle, against its projection floor (every (step, point, plane) of the 5 x 10
  degree grid, 325 planes in 3D, in one float32 product per chunk), in-plane and 3D; the
  compiled search where the tree has it (``PlaneSearch(compiled=True)``, after a warm-up:
  numba's load is the rig's), and the numpy search beside it; the floor into buffers
  allocated once, and the process with glibc's heap kept (``STEADY_HEAP``): before
  2026-11-27 the heap's state gave one side or the other fresh pages in about half the
  processes (the floor ~700 page faults a call, 2.45 ms against 1.40 ms in-plane);
- ``halfplane``: the half-plane body model's cycle (scene built cold, five steps) against the
  BEM bodies of the same scene and against a numpy Toeplitz influence-coefficient peer
  (``benchmarks/halfplane_peer.py``) on the same nodes, at 61 and 481 pairs, and the BEM
  bodies' cycle against the same peer; the process first runs both models on another pad
  (imports, compiled loops), so no geometry cache holds the measured scene, and the peer once
  (its imports). Then ``--cycles`` cycles, each a cold BEM cycle, a cold half-plane cycle
  (the scene builder's caches cleared before each: the BEM bodies' build would otherwise
  serve the half-plane one) and one peer run, so each side is measured in the state the
  others leave; the ratios are the medians of the per-cycle ratios (``bem_per_peer``,
  ``halfplane_per_peer``), the times the medians over cycles. Reported beside them: the
  first cycle alone (``bem_first``, ``halfplane_first``) and the peer's own best, five runs
  back to back after the cycles (``peer_warm`` their mean, ``peer_warm_best`` the fastest),
  with rows of each model's median cycle against that best warm run (the harshest reading).
  Before 2026-11-27 this workflow timed one cold cycle of ours per process against the
  mean of five warm back-to-back peer runs: one sample against a mean taken in another
  state. Measured in one process (load 1.6-3, three processes each): our first cycle and
  our back-to-back cycles read alike (BEM 481 pairs 345/359/403 ms first, 333/349/366
  back to back), while the peer read 2.56-3.75 ms warm and 2.77-4.11 interleaved at 61
  pairs, 62-69 and 56-66 ms at 481, and the ratio of one sample swung with either;
- ``sweep``: ``fretbem sweep examples/fretting_map.toml`` (144 cases) default engine against
  ``--serial``, whole process;
- ``demo``: ``fretbem demo`` with figures and VTK against ``python -c "import numpy,
  scipy.linalg"``, whole process, as it runs here (every installed family compared: a
  third-party family such as ``examples/custom_basis`` adds a solve and a curve per figure)
  and with the built-in families only (``--compare lagrange2``: what ``pip install . &&
  fretbem demo`` runs on a fresh machine); and the CPU seconds of drawing the demo's three PNGs
  (``save_figures`` of the demo's three 61-pair results, matplotlib already imported);
- ``memory``: the up-front memory estimate against the measured peak (VmHWM) of a 961-pair
  cycle.

    git archive b0bd220 | tar -x -C /tmp/before
    python benchmarks/workflows.py --before /tmp/before --rounds 3 \
        --json docs/results/workflows.json
    python benchmarks/performance_page.py

The small cycles and the demo (issue 28 items 3 and 4) against the code before that work:

    git archive 2e517d6 | tar -x -C /tmp/hp-before
    OPENBLAS_NUM_THREADS=1 python benchmarks/workflows.py --before /tmp/hp-before \
        --only halfplane demo --rounds 3 --json docs/results/workflows_small_cycles.json
    python benchmarks/performance_page.py
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

FATIGUE_CHILD = r"""
import json, time, statistics, numpy as np
from fretbem.fatigue import METHODS, CattaneoMindlinCycle, PlaneSearch, critical_plane_parameters
from fretbem.fatigue import last_full_reversal
from fretbem.fatigue.planes import plane_grid, projection
cm = CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5, sigma_bulk_max=80.0,
                          nu=0.342, steps_per_branch=2)
x, z = np.linspace(-0.75, 0.75, 100), np.linspace(0.0, 0.5, 100)
X, Z = np.meshgrid(x, z)
stress = cm.stress_at(np.stack([X.ravel(), Z.ravel()], axis=1))[last_full_reversal(cm.driver)]
consts = dict(findley_k=0.3, fatemi_socie_k=0.5, yield_strength=941.8)
# trees with the compiled search time it (and the numpy search beside it): the search's own
# cost after a warm-up, as before; loading numba is the whole process's (the rig workflow)
import attrs
paths = {"search": {"compiled": True}, "search_numpy": {"compiled": False}}
if "compiled" not in attrs.fields_dict(PlaneSearch):
    paths = {"search": {}}
out = {}
for in_plane in (True, False):
    search = PlaneSearch(in_plane_only=in_plane)
    # the floor of the 5 x 10 degree grid in every tree (the issue's floor; the default 3D
    # grid since issue 28 has 73 planes, checked against it: fatigue_3d_grid_study.py)
    th, ps = plane_grid(in_plane_only=in_plane, theta_step_deg=5.0, psi_step_deg=10.0)
    coef = projection(th, ps).astype(np.float32).transpose(2, 0, 1).reshape(4, -1)
    # into buffers allocated once: a fresh float32 copy and product per call read glibc's
    # heap state, not the product (fresh pages in half the processes: ~700 page faults a
    # call, the in-plane floor 2.45 ms against 1.40 ms; benchmarks/fatigue_phases.py)
    s32 = np.empty(stress.shape, dtype=np.float32)
    prod = np.empty((stress.shape[0], search.chunk_points, coef.shape[1]), dtype=np.float32)
    def floor():
        np.copyto(s32, stress, casting="same_kind")
        for a in range(0, s32.shape[1], search.chunk_points):
            part = s32[:, a:a + search.chunk_points]
            np.matmul(part, coef, out=prod[:, :part.shape[1]])
    def full(path):
        # the four critical-plane parameters (METHODS[:4]: the same in trees without
        # stress_life and strain_life, so before/after time the same work)
        critical_plane_parameters(stress, E=116000.0, nu=0.342, methods=METHODS[:4],
                                  search=PlaneSearch(in_plane_only=in_plane, **paths[path]),
                                  **consts)
    floor()
    for path in paths:
        full(path)
    tf, tc = [], {path: [] for path in paths}
    for _ in range(3):
        t = time.process_time(); floor(); tf.append(time.process_time() - t)
        for path in paths:
            t = time.process_time(); full(path); tc[path].append(time.process_time() - t)
    key = "in_plane" if in_plane else "3d"
    out[key] = {"floor": statistics.median(tf)}
    out[key].update({path: statistics.median(times) for path, times in tc.items()})
print(json.dumps(out))
"""

HALFPLANE_CHILD = r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[2])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
import halfplane_peer
from cold_caches import clear_scene_caches
pairs, cycles = int(sys.argv[1]), int(sys.argv[3])
models = {"bem": {}, "halfplane": {"upper": "half-plane", "lower": "half-plane"}}
for m in models.values():  # imports, compiled loops: on another pad, so no cache holds the scene;
    for _ in range(2):  # twice: the pad's second assembly crosses the compiled loops' threshold
        # where its image specimen's used to (it now takes the pad's H and G, unassembled)
        run(scenes.cattaneo_mindlin(pairs=pairs, models=m, radius=71.0))
halfplane_peer.cycle(pairs)  # the peer's imports and first call
def cold(m):  # scene build + five steps, the scene builder's caches cleared first
    clear_scene_caches()  # cold for each model: the other model's run built the same shapes
    c = time.process_time()
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models=m)
    built = time.process_time() - c
    run(simulation)
    return built, time.process_time() - c
def peer():
    t = time.process_time()
    halfplane_peer.cycle(pairs)
    return time.process_time() - t
rows = []
for _ in range(cycles):  # interleaved: each cycle measured as the other sides are
    row = {}
    for name, m in models.items():
        row[name + "_build"], row[name] = cold(m)
    row["peer"] = peer()
    rows.append(row)
out = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
for name in models:  # the median of the per-cycle ratios
    out[name + "_per_peer"] = statistics.median(r[name] / r["peer"] for r in rows)
out["bem_first"], out["halfplane_first"] = rows[0]["bem"], rows[0]["halfplane"]
warm = [peer() for _ in range(5)]  # the peer's own best: back to back after the cycles
out["peer_warm"], out["peer_warm_best"] = statistics.mean(warm), min(warm)
print(json.dumps(out))
"""

FIGURES_CHILD = r"""
import json, tempfile, time
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
# what the demo draws: nurbs and every other installed family of 61 pairs
results = [run(cattaneo_mindlin(basis=b, pairs=61)) for b in ("nurbs", "lagrange2", "lagrange3")]
t = time.process_time()
from fretbem.output import figures
import matplotlib.backends.backend_agg, matplotlib.figure
out = {"import": time.process_time() - t}
with tempfile.TemporaryDirectory() as directory:  # the demo's three PNGs, once per process
    t = time.process_time()
    figures.save_figures(results, directory)
    out["figures"] = time.process_time() - t
print(json.dumps(out))
"""

MEMORY_CHILD = r"""
import json, sys
from fretbem.bem import resources
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
simulation = cattaneo_mindlin(basis="nurbs", pairs=int(sys.argv[1]))
dofs = simulation.pair.upper.dofs + simulation.pair.lower.dofs
# the estimate the run is checked with (its body models and compiled loops, where the tree
# counts them)
size = resources.run_size(simulation.pair) if hasattr(resources, "run_size") else {"dofs": dofs}
run(simulation)
with open("/proc/self/status") as fh:
    peak = [int(l.split()[1]) * 1024 for l in fh if l.startswith("VmHWM")][0]
estimate = resources.estimate_resources(**size, available=None).memory
print(json.dumps({"dofs": dofs, "estimate": estimate, "peak": peak}))
"""


def _env(tree: Path) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
    env["OPENBLAS_NUM_THREADS"] = env["OMP_NUM_THREADS"] = "1"
    env["MPLBACKEND"] = "Agg"
    return env


#: glibc's allocator for the fatigue child: freed memory kept (no trim), arrays under 32 MiB
#: from the heap. With its defaults the heap's state decided whether a side's arrays came back
#: on fresh pages: measured in fresh processes (load 6-8), the floor's float32 copy and
#: products ~700 page faults a call in 4 of 8 processes (in-plane 2.45 ms against 1.40 ms),
#: and with the floor's buffers allocated once, the search's outputs 358-496 faults a call in
#: 5 of 6 (10.3-11.3 ms against 9.4-9.6 ms); with these settings no fault on either side in
#: any process, the state both sides read in one process (benchmarks/fatigue_phases.py)
STEADY_HEAP = "glibc.malloc.trim_threshold=1073741824:glibc.malloc.mmap_threshold=33554432"


def _process(
    args: list[str], tree: Path, cwd: Path, extra: dict | None = None
) -> tuple[float, float, str]:
    """(wall s, CPU s of the process and its children, stdout) of one fresh process
    (``extra``: environment variables besides the tree's)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        args, env={**_env(tree), **(extra or {})}, cwd=cwd, capture_output=True, text=True,
        check=False,
    )  # fmt: skip
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed:\n{done.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout


def _cli(tree: Path, *args: str) -> list[str]:
    return [sys.executable, "-m", "fretbem.app.cli", *args]


def rig_plain(tree: Path, tmp: Path) -> Path:
    """The tree's examples/fretting_rig.toml without its [stress] and [fatigue] tables."""
    text = (tree / "examples" / "fretting_rig.toml").read_text()
    path = tmp / "rig_plain.toml"
    path.write_text(text[: text.index("[stress]")])
    return path


def compile_tree(tree: Path) -> None:
    """The tree's bytecode written once, as ``pip install`` leaves it: with
    PYTHONDONTWRITEBYTECODE set (this machine) every process would compile fretbem's ~170
    modules again (0.25-0.3 s CPU) while numpy, scipy and matplotlib load theirs."""
    folders = [str(tree / name) for name in ("framework", "plugins")]
    subprocess.run([sys.executable, "-m", "compileall", "-q", *folders], check=True,
                   capture_output=True)  # fmt: skip


def one_round(tree: Path, tmp: Path, which: set[str], index: int = 0, cycles: int = 5) -> dict:
    """Every workflow once on ``tree`` (its own example files: scene keys may differ); the
    sweep's two engines alternate which runs first with the round ``index``; the small
    cycles take ``cycles`` interleaved cold cycles."""
    out: dict = {}
    work = Path(tempfile.mkdtemp(dir=tmp))
    if "rig" in which:
        full = _process(_cli(tree, "run", str(tree / "examples" / "fretting_rig.toml"),
                             "--out", str(work / "rig")), tree, work)  # fmt: skip
        plain_scene = str(rig_plain(tree, work))
        plain = _process(_cli(tree, "run", plain_scene, "--out", str(work / "plain")), tree, work)
        out["rig"] = {"full_wall": full[0], "full_cpu": full[1],
                      "plain_wall": plain[0], "plain_cpu": plain[1]}  # fmt: skip
    if "fatigue" in which:
        child = _process([sys.executable, "-c", FATIGUE_CHILD], tree, work,
                         {"GLIBC_TUNABLES": STEADY_HEAP})  # fmt: skip
        out["fatigue"] = json.loads(child[2])
    if "halfplane" in which:
        for pairs in (61, 481):
            text = _process([sys.executable, "-c", HALFPLANE_CHILD, str(pairs),
                             str(ROOT / "benchmarks"), str(cycles)], tree, work)[2]  # fmt: skip
            out[f"halfplane_{pairs}"] = json.loads(text)
    if "sweep" in which:
        example = str(tree / "examples" / "fretting_map.toml")
        engines = {"auto": (), "serial": ("--serial",)}
        sweeps = {}
        for name in list(engines)[:: 1 if index % 2 == 0 else -1]:
            sweeps[name] = _process(_cli(tree, "sweep", example, *engines[name], "--out",
                                         str(work / name), "--no-figures"), tree, work)  # fmt: skip
        auto, serial = sweeps["auto"], sweeps["serial"]
        out["sweep"] = {"default_wall": auto[0], "default_cpu": auto[1],
                        "serial_wall": serial[0], "serial_cpu": serial[1]}  # fmt: skip
    if "demo" in which:
        demo = _process(_cli(tree, "demo", "--out", str(work / "demo")), tree, work)
        # the demo as `pip install .` gives it: the two built-in families, whatever else
        # this machine has installed (the default compares every installed family)
        builtin = _process(_cli(tree, "demo", "--compare", "lagrange2", "--out",
                                str(work / "demo_builtin")), tree, work)  # fmt: skip
        floor = _process([sys.executable, "-c", "import numpy, scipy.linalg"], tree, work)
        out["demo"] = {"demo_wall": demo[0], "demo_cpu": demo[1],
                       "builtin_wall": builtin[0], "builtin_cpu": builtin[1],
                       "floor_wall": floor[0], "floor_cpu": floor[1]}  # fmt: skip
        out["figures"] = json.loads(_process([sys.executable, "-c", FIGURES_CHILD], tree, work)[2])
    if "memory" in which:
        out["memory"] = json.loads(
            _process([sys.executable, "-c", MEMORY_CHILD, "961"], tree, work)[2]
        )
    return out


def _median(rounds: list[dict]) -> dict:
    """Median of every leaf over the rounds."""
    first = rounds[0]
    if isinstance(first, dict):
        return {k: _median([r[k] for r in rounds]) for k in first}
    return statistics.median(rounds)


def ratios(m: dict) -> dict:
    """The issue's ratios from one tree's medians."""
    r = {}
    if "rig" in m:
        r["rig: with [stress]+[fatigue] / without (CPU)"] = (
            m["rig"]["full_cpu"] / m["rig"]["plain_cpu"]
        )
        r["rig: with [stress]+[fatigue] / without (wall)"] = (
            m["rig"]["full_wall"] / m["rig"]["plain_wall"]
        )
    if "fatigue" in m:
        for key, label in (("in_plane", "in-plane"), ("3d", "3D")):
            f = m["fatigue"][key]
            r[f"fatigue search {label} / projection floor"] = f["search"] / f["floor"]
            if "search_numpy" in f:
                r[f"fatigue search {label}, numpy path / projection floor"] = (
                    f["search_numpy"] / f["floor"]
                )
    for pairs in (61, 481):
        h = m.get(f"halfplane_{pairs}")
        if h:  # medians of the per-cycle ratios (a JSON of before this method: of the times)
            for name, label in (("halfplane", "half-plane body"), ("bem", "BEM bodies")):
                r[f"{label} / numpy Toeplitz peer, {pairs} pairs"] = h.get(
                    f"{name}_per_peer", h[name] / h["peer"]
                )
            r[f"half-plane body / BEM bodies, {pairs} pairs"] = h["halfplane"] / h["bem"]
            if "peer_warm_best" in h:  # against the peer's own best, back to back, warm
                for name, label in (("halfplane", "half-plane body"), ("bem", "BEM bodies")):
                    r[f"{label} / the peer's best warm run, {pairs} pairs"] = (
                        h[name] / h["peer_warm_best"]
                    )
    if "sweep" in m:
        s = m["sweep"]
        r["sweep default / --serial, 144 cases (wall)"] = s["default_wall"] / s["serial_wall"]
        r["sweep default / --serial, 144 cases (CPU)"] = s["default_cpu"] / s["serial_cpu"]
    if "demo" in m:
        d = m["demo"]
        r["demo / numpy+scipy.linalg import (wall)"] = d["demo_wall"] / d["floor_wall"]
        r["demo / numpy+scipy.linalg import (CPU)"] = d["demo_cpu"] / d["floor_cpu"]
        if "builtin_cpu" in d:
            r["demo, built-in families only / import (CPU)"] = d["builtin_cpu"] / d["floor_cpu"]
    if "figures" in m:
        r["demo's three PNGs, drawing (CPU s)"] = m["figures"]["figures"]
    if "memory" in m:
        r["memory estimate / measured peak, 961 pairs"] = (
            m["memory"]["estimate"] / m["memory"]["peak"]
        )
    return r


ALL = ("rig", "fatigue", "halfplane", "sweep", "demo", "memory")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="source tree of the old code")
    parser.add_argument("--after", type=Path, default=ROOT, help="source tree of the new code")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument(
        "--cycles", type=int, default=5,
        help="interleaved cold cycles per process in the halfplane workflow",
    )  # fmt: skip
    parser.add_argument("--only", nargs="*", choices=ALL, default=list(ALL))
    parser.add_argument("--json", type=Path)
    parser.add_argument(
        "--source-only", action="store_true",
        help="do not write the trees' bytecode first (every process compiles fretbem)",
    )  # fmt: skip
    args = parser.parse_args()
    trees = {"after": args.after.resolve()}
    if args.before:
        trees = {"before": args.before.resolve(), **trees}
    if not args.source_only:
        for tree in trees.values():
            compile_tree(tree)
    load = [os.getloadavg()[0]]
    runs: dict[str, list] = {k: [] for k in trees}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.rounds):
            for label, tree in trees.items():
                runs[label].append(one_round(tree, Path(tmp), set(args.only), k, args.cycles))
                print(f"round {k + 1} {label} done, load {os.getloadavg()[0]:.2f}", flush=True)
    load.append(os.getloadavg()[0])
    result = {
        "machine": f"{os.cpu_count()} cores, {platform.platform()}, Python "
        f"{platform.python_version()}",
        "load": load,
        "rounds": args.rounds,
        "bytecode": "source only" if args.source_only else "compiled first (compileall)",
        "medians": {k: _median(v) for k, v in runs.items()},
    }
    result["ratios"] = {k: ratios(v) for k, v in result["medians"].items()}
    for name in result["ratios"]["after"]:
        cells = [f"{result['ratios'][k].get(name, float('nan')):8.2f}" for k in trees]
        print(f"{name:58s}" + "".join(cells))
    if args.json:
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
