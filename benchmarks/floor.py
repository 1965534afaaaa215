"""Issue 16's budget: assembly against a compiled floor, cycle against DOFs, memory, demo.

Measured in one process where ratios matter (interleaved rounds, medians), the load
average noted; the machine may be shared, so compare ratios rather than seconds.

- ``floor``: one body's H and G (the scene's pad) at 61 and 481 pairs, both families,
  against the *floor*: a numba kernel integrating every (collocation point, element) pair
  with the far-field rule straight into dense H and G, no classification and no near or
  singular work (:func:`fretbem.bem.compiled_loops.dense_far_field`): the least work any assembler
  using that rule must do. Both assembly paths are timed (numpy, compiled) when present;
- ``cycle``: the reference five-step cycle at 61, 481, 961 (and 1921 with --large) pairs,
  per phase (assembly, factorisation, condensation, steps), against DOFs, with fitted
  exponents;
- ``memory``: the peak resident set (VmHWM growth over the imports) and tracemalloc peak of
  the whole cycle in a fresh process, against DOFs; the peak factor is the peak over the
  dense storage of H and G of both bodies (2 bodies x 2 matrices x DOFs^2 x 8 bytes);
- ``demo``: ``fretbem demo`` as a whole process: --no-figures --no-vtk, and with both.

Run from the repository root (about 2 minutes without --large, ~5 more with it)::

    python benchmarks/floor.py --json docs/results/performance.json --label after --large
    python benchmarks/performance_page.py   # regenerates docs/performance.md
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from threadpoolctl import threadpool_limits

from fretbem.bem import integration
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

FAMILIES = ("nurbs", "lagrange2")
TARGETS = {
    "cycle_61": 0.060,
    "cycle_961": 4.0,
    "cycle_1921": 20.0,
    "memory_1921_mib": 1536.0,
    "demo_full": 1.5,
    "demo_bare": 0.6,
}


def machine() -> dict:
    return {
        "cores": os.cpu_count(),
        "processor": platform.processor() or platform.machine(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "load_average_start": os.getloadavg()[0],
    }


def _assembler(body, **settings):
    """An Assembler for ``body`` with the given IntegrationSettings overrides (either API)."""
    fields = _settings_dict(integration.IntegrationSettings())
    given = {k: v for k, v in settings.items() if k in fields}
    config = integration.IntegrationSettings(**{**_settings_dict(body.integration), **given})
    try:
        from fretbem.bem.kernels import KelvinKernel

        return integration.Assembler(body.segments, KelvinKernel.of(body.material), config)
    except (ImportError, AttributeError, TypeError):
        material = body.material
        return integration.Assembler(
            body.segments, material.shear_modulus, material.kernel_nu, config
        )


def _settings_dict(settings) -> dict:
    return {a.name: getattr(settings, a.name) for a in type(settings).__attrs_attrs__}


def _has_compiled() -> bool:
    return "compiled" in _settings_dict(integration.IntegrationSettings())


def _round_one():
    """The frozen round-1 assembler of the tests, when the tests are next to this file."""
    here = os.path.dirname(os.path.abspath(__file__))
    tests = os.path.join(os.path.dirname(here), "tests", "framework")
    if not os.path.exists(os.path.join(tests, "frozen_assembly_round1.py")):
        return None
    sys.path.insert(0, tests)
    try:
        import frozen_assembly_round1
    finally:
        sys.path.remove(tests)
    return frozen_assembly_round1


def _floor(body):
    """The compiled floor for ``body``: far rule on every pair, dense H and G."""
    from fretbem.bem import compiled_loops as _compiled

    segments = body.segments
    offsets = integration.offsets(segments)
    n = int(offsets[-1])
    points = integration.Collocation.of(segments).points
    rule = QuadratureRule.gauss_legendre(body.integration.far_points)
    data = []
    for k, basis in enumerate(segments):
        n_el, q = basis.n_elements, rule.points.size
        m = basis.map(np.repeat(np.arange(n_el), q), np.tile(rule.points, n_el))
        x, normals = m.points.reshape(n_el, q, 2), m.normals.reshape(n_el, q, 2)
        jw, phi = m.jacobians.reshape(n_el, q) * rule.weights, m.values.reshape(n_el, q, -1)
        cols = offsets[k] + basis.connectivity
        data.append(tuple(np.ascontiguousarray(a) for a in (x, normals, jw, phi, cols)))
    mu, nu = body.material.shear_modulus, body.material.kernel_nu
    evaluations = n * sum(d[0].shape[0] * d[0].shape[1] for d in data)

    def floor():
        h, g = np.zeros((2 * n, 2 * n)), np.zeros((2 * n, 2 * n))
        for x, normals, jw, phi, cols in data:
            _compiled.dense_far_field(points, x, normals, jw, phi, cols, mu, nu, h, g)
        return h, g

    return floor, evaluations


def bench_floor(args, out: dict) -> None:
    """Assembly of one body against the compiled floor, interleaved rounds."""
    rows = []
    for family in FAMILIES:
        for pairs in (61, 481):
            body = cattaneo_mindlin(basis=family, pairs=pairs).pair.upper
            floor, evaluations = _floor(body)
            candidates = {"floor": floor}
            round1 = _round_one()
            if round1 is not None:  # the round-1 assembler, frozen: "before" in this process
                material = body.material
                mu, nu = material.shear_modulus, material.kernel_nu
                candidates["round1"] = lambda b=body, mu=mu, nu=nu, r=round1: r.Assembler(
                    b.segments, mu, nu
                ).assemble()
            if _has_compiled():
                candidates["numpy"] = lambda b=body: _assembler(b, compiled=False).assemble()
                candidates["compiled"] = lambda b=body: _assembler(b, compiled=True).assemble()
            else:
                candidates["numpy"] = lambda b=body: _assembler(b).assemble()
            times = {k: [] for k in candidates}
            for f in candidates.values():
                f()  # warm-up (and the first compile, if any)
            rounds = args.runs if pairs <= 61 else max(3, args.runs // 2)
            for _ in range(rounds):
                for name, f in candidates.items():
                    tic = time.perf_counter()
                    f()
                    times[name].append(time.perf_counter() - tic)
            med = {k: statistics.median(v) for k, v in times.items()}
            row = {
                "family": family,
                "pairs": pairs,
                "dofs": body.dofs,
                "evaluations": evaluations,
                "floor_rate": evaluations / med["floor"],
                "seconds": med,
                "ratio": {k: v / med["floor"] for k, v in med.items() if k != "floor"},
            }
            rows.append(row)
            ratios = ", ".join(f"{k} {v:.2f}x" for k, v in row["ratio"].items())
            print(
                f"{family:9s} {pairs:4d} pairs, {body.dofs} DOFs: floor "
                f"{med['floor'] * 1e3:.1f} ms ({row['floor_rate'] / 1e6:.1f} M evaluations/s); "
                f"{ratios}",
                flush=True,
            )
    out["floor"] = rows


def _cycle(family: str, pairs: int) -> tuple[dict, int, list[int]]:
    sim = cattaneo_mindlin(basis=family, pairs=pairs)
    result = run(sim)
    dofs = sim.pair.upper.dofs + sim.pair.lower.dofs
    return dict(result.timings), dofs, [s.iterations for s in result.steps]


def bench_cycle(args, out: dict) -> None:
    """The five-step cycle per phase against pairs (medians of several runs when cheap).

    In-process: once the floor benchmark has loaded the compiled kernels, every assembly
    uses them (as in any long-lived process); ``compiled_loaded`` records it.
    """
    sizes = [61, 481, 961] + ([1921] if args.large else [])
    rows = []
    for pairs in sizes:
        runs = args.runs if pairs <= 61 else (3 if pairs <= 481 else 1)
        if pairs <= 61:
            _cycle("nurbs", pairs)  # warm-up: first-call costs
        parts = [_cycle("nurbs", pairs) for _ in range(runs)]
        timings = {k: statistics.median(p[0][k] for p in parts) for k in parts[0][0]}
        rows.append(
            {
                "pairs": pairs,
                "dofs": parts[0][1],
                "iterations": parts[0][2],
                "timings": timings,
                "compiled_loaded": "fretbem.bem.compiled_loops" in sys.modules,
            }
        )
        phases = ", ".join(f"{k} {v:.3f}" for k, v in timings.items())
        print(f"cycle nurbs {pairs:5d} pairs, {parts[0][1]} DOFs: {phases} s", flush=True)
    out["cycle"] = rows
    dofs = np.array([r["dofs"] for r in rows], float)
    out["cycle_exponents"] = {
        phase: float(
            np.polyfit(np.log(dofs[1:]), np.log([r["timings"][phase] for r in rows[1:]]), 1)[0]
        )
        for phase in rows[0]["timings"]
        if len(rows) > 2 and all(r["timings"][phase] > 0 for r in rows[1:])
    }


MEMORY_PROBE = """
import sys, tracemalloc
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run

def high_water():
    with open("/proc/self/status") as status:
        return int(next(x for x in status if x.startswith("VmHWM:")).split()[1]) * 1024

sim = cattaneo_mindlin(basis={family!r}, pairs={pairs})
before = high_water()
{trace}
run(sim)
peak = tracemalloc.get_traced_memory()[1] if tracemalloc.is_tracing() else 0
print(sim.pair.upper.dofs + sim.pair.lower.dofs, before, high_water(), peak)
"""


def bench_memory(args, out: dict) -> None:
    """Peak memory of the whole cycle in a fresh process against DOFs (Linux VmHWM)."""
    sizes = [61, 241, 481, 961] + ([1921] if args.large else [])
    rows = []
    for pairs in sizes:
        code = MEMORY_PROBE.format(family="nurbs", pairs=pairs, trace="")
        text = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        ).stdout.split()
        dofs, before, after, _ = (int(v) for v in text[-4:])
        dense = 2 * 2 * (dofs // 2) ** 2 * 8  # two bodies of dofs/2, H and G each
        row = {
            "pairs": pairs,
            "dofs": dofs,
            "peak_rss_growth_bytes": after - before,
            "peak_rss_bytes": after,
            "dense_hg_bytes": dense,
            "peak_factor": (after - before) / dense,
        }
        rows.append(row)
        print(
            f"memory nurbs {pairs:5d} pairs, {dofs} DOFs: peak RSS {after / 2**20:.0f} MiB "
            f"({(after - before) / 2**20:.0f} MiB over the imports), dense H+G "
            f"{dense / 2**20:.0f} MiB, factor {row['peak_factor']:.2f}",
            flush=True,
        )
    out["memory"] = rows


def bench_demo(args, out: dict) -> None:
    """Whole-process ``fretbem demo``: bare (no figures, no VTK) and full."""
    script = shutil.which("fretbem")
    command = [script] if script else [sys.executable, "-m", "fretbem.app.cli"]
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, flags in (("demo_bare", ["--no-figures", "--no-vtk"]), ("demo_full", [])):
            runs = []
            for k in range(args.runs + 1):
                tic = time.perf_counter()
                subprocess.run(
                    [*command, "demo", *flags, "--out", os.path.join(tmp, f"{name}{k}")],
                    check=True,
                    capture_output=True,
                )
                runs.append(time.perf_counter() - tic)
            rows[name] = {"flags": flags, "runs": runs[1:], "median": statistics.median(runs[1:])}
            print(
                f"fretbem demo {' '.join(flags)}: median {rows[name]['median']:.3f} s", flush=True
            )
    out["demo"] = rows


BENCHMARKS = {
    "floor": bench_floor,
    "cycle": bench_cycle,
    "memory": bench_memory,
    "demo": bench_demo,
}


def _merge(old: dict, new: dict) -> None:
    """Update ``old`` with ``new``; rows of a series are replaced size by size, so a run of
    some sizes (e.g. --large alone) keeps the others."""
    for key, value in new.items():
        if isinstance(value, list) and isinstance(old.get(key), list):
            ident = (lambda r: (r.get("family"), r["pairs"])) if value else None
            rows = {ident(r): r for r in old[key]}
            rows.update({ident(r): r for r in value})
            old[key] = sorted(rows.values(), key=lambda r: (str(r.get("family")), r["pairs"]))
        else:
            old[key] = value


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", choices=list(BENCHMARKS), default=list(BENCHMARKS))
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--large", action="store_true", help="include 1921 pairs (minutes)")
    parser.add_argument(
        "--label", default="after", help="'before' or 'after' (the page pairs them)"
    )
    parser.add_argument("--json", help="merge the results into this JSON file under --label")
    args = parser.parse_args(argv)
    out: dict = {"machine": machine()}
    print(
        f"{out['machine']['cores']} cores, {out['machine']['platform']}, load average "
        f"{out['machine']['load_average_start']:.2f}"
    )
    with threadpool_limits(limits=1, user_api="blas"):  # a shared machine: one BLAS thread
        for name in args.only:
            BENCHMARKS[name](args, out)
    out["machine"]["load_average_end"] = os.getloadavg()[0]
    if args.json:
        data = {}
        if os.path.exists(args.json):
            with open(args.json) as handle:
                data = json.load(handle)
        _merge(data.setdefault(args.label, {}), out)
        with open(args.json, "w") as handle:
            json.dump(data, handle, indent=1, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
