"""The convergence study with every knob: families, levels, repeats, memory tracing.

``fretbem convergence [--quick] [--out DIR]`` runs the default plans; this script runs any
plan, e.g. one family at a few levels with more timed repeats::

    python benchmarks/convergence_study.py --out study --repeats 5
    python benchmarks/convergence_study.py --families nurbs:2 lagrange2 --pairs 61 121 241
    OPENBLAS_NUM_THREADS=1 python benchmarks/convergence_study.py --out docs/results

It writes convergence.csv, study.json and the two figures into --out; make the results
page from them with benchmarks/results_page.py.
"""

from __future__ import annotations

import argparse
import os

import attrs

from fretbem.studies.convergence import StudyPlan, run_study


def family(text: str) -> tuple[str, int | None]:
    name, _, degree = text.partition(":")
    return name, int(degree) if degree else None


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="start from the quick (CI) plan")
    parser.add_argument("--out", default="convergence-out")
    parser.add_argument("--families", nargs="+", type=family, help="e.g. nurbs:3 lagrange2")
    parser.add_argument("--pairs", nargs="+", type=int, help="levels on the scene's bodies")
    parser.add_argument("--large-pairs", nargs="*", type=int, help="levels on 4x bodies")
    parser.add_argument("--rest-pairs", nargs="*", type=int, help="levels of the rest check")
    parser.add_argument("--rest-factors", nargs="*", type=float)
    parser.add_argument("--repeats", type=int, help="timed runs per case (median)")
    parser.add_argument("--no-memory", action="store_true", help="skip the tracemalloc runs")
    parser.add_argument("--no-figures", action="store_true")
    args = parser.parse_args(argv)
    plan = StudyPlan.quick() if args.quick else StudyPlan.full()
    changes = {
        "families": tuple(args.families) if args.families else None,
        "pairs": tuple(args.pairs) if args.pairs else None,
        "large_pairs": None if args.large_pairs is None else tuple(args.large_pairs),
        "rest_pairs": None if args.rest_pairs is None else tuple(args.rest_pairs),
        "rest_factors": None if args.rest_factors is None else tuple(args.rest_factors),
        "repeats": args.repeats,
        "memory": False if args.no_memory else None,
    }
    plan = attrs.evolve(plan, **{k: v for k, v in changes.items() if v is not None})
    print(f"{os.cpu_count()} cores; plan: {attrs.asdict(plan)}")
    run_study(plan, args.out, figures=not args.no_figures)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
