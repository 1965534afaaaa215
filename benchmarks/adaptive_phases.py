"""Where a cold adaptive run at budget 61 spends its CPU, beside the fixed run with its
estimate (issue 28: the ratio of ``adaptive_cost.py``), in one process.

Each phase is the CPU time inside one function of the run, summed over its calls (timers
wrapped around the functions, so phases nest: ``prepare`` holds ``assembly`` and
``factorisation``); medians of ``--rounds`` cold runs (every cache emptied as in
``adaptive_cost.py``), the two workloads interleaved. The split says what a faster
adaptive mode has to remove: the level solves (how many, and what each costs) against the
mode's own work (re-meshing, knots, estimate), and the Newton iterations of each mode.

    OPENBLAS_NUM_THREADS=1 python benchmarks/adaptive_phases.py --rounds 9

``--knot-starts`` times instead the adaptive run with and without its levels' knot starts
(:class:`fretbem.solvers.warm_start.WarmStart` ``knots``), interleaved in one process.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from adaptive_cost import cases, clear_caches

#: (label, module, function or Class.method); an indented phase is timed only inside the
#: phase above it with less indentation (its parent)
PHASES = (
    ("scene build", "fretbem.scenes.builder", "build"),
    ("level solves (run)", "fretbem.simulation", "run"),
    ("  prepare (condensation)", "fretbem.contact.condensation", "CondensedContact.build"),
    ("    assembly", "fretbem.bem.integration", "Assembler.assemble"),
    ("    factorisation + parameters", "fretbem.bem.system", "_solve_parameters"),
    ("    image body's parameters", "fretbem.bem.system", "_permuted_parameters"),
    ("  steps (Newton, records)", "fretbem.simulation", "Simulation.step"),
    ("  step results and checks", "fretbem.results", "StepResult.build"),
    ("re-meshing", "fretbem.accuracy.remesh", "remesh"),
    ("  layouts", "fretbem.accuracy.remesh", "_fitted_layout"),
    ("    faces discretised", "fretbem.bem.images", "discretise"),
    ("  pairs' faces (collocation)", "fretbem.bem.body", "BemBody.contact_face"),
    ("  pairing", "fretbem.contact.pairs", "NodeToNodePair._pair_up"),
    ("knot moves", "fretbem.accuracy.knots", "knot_moves"),
    ("transitions (incl. refound)", "fretbem.accuracy.knots", "transitions"),
    ("estimate", "fretbem.accuracy.estimate", "estimate_errors"),
)


#: how many calls of each phase are running
ACTIVE: dict = {}


def _wrap(totals: dict, label: str, module: str, name: str, parent: str | None) -> None:
    """Time ``module.name`` (a function or ``Class.method``) under ``label`` in ``totals``;
    the name is replaced wherever the run's modules imported it. A level solve (``run``)
    also adds its Newton iterations under "iterations". With a ``parent`` label, only the
    calls made while that phase runs count."""
    owner = importlib.import_module(module)
    attr = name
    if "." in name:
        cls, attr = name.split(".")
        owner = getattr(owner, cls)
    original = getattr(owner, attr)

    @functools.wraps(original)
    def timed(*args, **kwargs):
        if parent is not None and not ACTIVE.get(parent):
            return original(*args, **kwargs)
        start = time.process_time()
        ACTIVE[label] = ACTIVE.get(label, 0) + 1
        try:
            result = original(*args, **kwargs)
        finally:
            ACTIVE[label] -= 1
            totals[label] = totals.get(label, 0.0) + time.process_time() - start
        if name == "run":
            iterations = sum(step.iterations for step in result.steps)
            totals["iterations"] = totals.get("iterations", 0) + iterations
        return result

    setattr(owner, attr, timed)
    if "." not in name:  # modules that imported the function by name
        for other in list(sys.modules.values()):
            if getattr(other, "__name__", "").startswith("fretbem") and (
                getattr(other, attr, None) is original
            ):
                setattr(other, attr, timed)


def _depth(label: str) -> int:
    return len(label) - len(label.lstrip())


def _parent(k: int) -> str | None:
    """The label of phase ``k``'s parent (the nearest phase above it indented less)."""
    depth = _depth(PHASES[k][0])
    for label, *_ in reversed(PHASES[:k]):
        if _depth(label) < depth:
            return label
    return None


def measure(rounds: int) -> dict:
    """Per workload: the median total and phases (CPU s), and Newton iterations."""
    import fretbem.bem.compiled_loops  # noqa: F401  (the same loops in every round)

    work = {k: v for k, v in cases(61).items() if k != "fixed"}
    for fn in work.values():  # imports, kernels
        fn()
    totals: dict = {}
    for k, (label, module, name) in enumerate(PHASES):
        _wrap(totals, label, module, name, _parent(k))
    rows: dict = {name: [] for name in work}
    for _ in range(rounds):
        for name, fn in work.items():
            clear_caches()
            totals.clear()
            start = time.process_time()
            result = fn()
            record = dict(totals, total=time.process_time() - start)
            rows[name].append((record, list(result.accuracy.get("levels") or [])))
    out = {}
    for name, runs in rows.items():
        keys = {k for record, _ in runs for k in record}
        out[name] = {
            "median": {k: statistics.median(r.get(k, 0.0) for r, _ in runs) for k in keys},
            "levels": runs[0][1],
        }
    return out


def knot_starts(rounds: int) -> None:
    """Median CPU of the cold adaptive run with and without the knot starts, interleaved."""
    import fretbem.bem.compiled_loops  # noqa: F401  (the same loops in every round)
    from fretbem.accuracy import adaptive

    run = cases(61)["adaptive"]
    run()
    told = adaptive._solve

    def untold(simulation, after=None, knots=None):
        return told(simulation, after, None)

    times: dict = {"with knot starts": [], "without": []}
    for _ in range(rounds):
        for name, solve in (("with knot starts", told), ("without", untold)):
            adaptive._solve = solve
            clear_caches()
            start = time.process_time()
            run()
            times[name].append(time.process_time() - start)
    adaptive._solve = told
    medians = {name: statistics.median(values) for name, values in times.items()}
    for name, value in medians.items():
        print(f"adaptive, {name:18s} {1e3 * value:7.1f} ms CPU")
    print(f"with / without {medians['with knot starts'] / medians['without']:.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--knot-starts", action="store_true", help="time the knot starts")
    args = parser.parse_args()
    if args.knot_starts:
        load = os.getloadavg()[0]
        knot_starts(args.rounds)
        print(f"load average {load:.1f} -> {os.getloadavg()[0]:.1f}")
        return
    load = os.getloadavg()[0]
    out = measure(args.rounds)
    names = list(out)
    print(f"{'CPU ms (median of ' + str(args.rounds) + ' cold runs)':40s}" + "".join(
        f"{n:>16s}" for n in names))  # fmt: skip
    for label, *_ in (("total",), *PHASES):
        cells = "".join(f"{1e3 * out[n]['median'].get(label, 0.0):16.1f}" for n in names)
        print(f"{label:40s}{cells}")
    for name in names:
        m = out[name]["median"]
        own = m["total"] - m.get("scene build", 0.0) - m.get("level solves (run)", 0.0)
        print(
            f"{name}: levels {out[name]['levels']}, {m.get('iterations', 0):.0f} Newton "
            f"iterations; outside the scene build and the level solves {1e3 * own:.1f} ms"
        )
    a, f = out["adaptive"]["median"], out["fixed+estimate"]["median"]
    print(f"adaptive / fixed+estimate {a['total'] / f['total']:.2f}; with the mode's own work "
          f"free (scene build and level solves only) "
          f"{(a.get('scene build', 0) + a['level solves (run)']) / f['total']:.2f}")  # fmt: skip
    print(f"load average {load:.1f} -> {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
