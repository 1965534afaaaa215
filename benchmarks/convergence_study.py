"""The convergence study with every knob: families, levels, budgets, repeats, memory tracing.

``fretbem convergence [--quick] [--out DIR]`` runs the default plans; this script runs any
plan, e.g. one family at a few levels with more timed repeats::

    python benchmarks/convergence_study.py --out study --repeats 5
    python benchmarks/convergence_study.py --families nurbs:2 lagrange2 --pairs 61 121 241
    python benchmarks/convergence_study.py --budgets 41 61 --sawtooth 31 61

It writes convergence.csv, adaptive_study.csv, adaptive_study_sawtooth.csv, study.json and
the three figures into --out; with --page it also writes the results page from them (what
benchmarks/results_page.py does). The whole of docs/results and docs/results.md, in one
command (one BLAS thread, as the page says)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/convergence_study.py --out docs/results \\
        --page docs/results.md \\
        --benchmarks docs/results/benchmarks-1thread.json docs/results/benchmarks-default.json
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import attrs

from fretbem.studies.convergence.study import CSV_NAME, StudyPlan, run_study


def family(text: str) -> tuple[str, int | None]:
    name, _, degree = text.partition(":")
    return name, int(degree) if degree else None


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="start from the quick (CI) plan")
    parser.add_argument("--out", default="convergence-out")
    parser.add_argument("--families", nargs="+", type=family, help="e.g. nurbs:3 lagrange2")
    parser.add_argument("--pairs", nargs="*", type=int, help="levels on the scene's bodies")
    parser.add_argument("--large-pairs", nargs="*", type=int, help="levels on 4x bodies")
    parser.add_argument("--rest-pairs", nargs="*", type=int, help="levels of the rest check")
    parser.add_argument("--rest-factors", nargs="*", type=float)
    parser.add_argument("--repeats", type=int, help="timed runs per case (median)")
    parser.add_argument("--no-memory", action="store_true", help="skip the tracemalloc runs")
    parser.add_argument(
        "--adaptive-families", nargs="+", type=family, help="families of the adaptive series"
    )
    parser.add_argument("--budgets", nargs="*", type=int, help="pair budgets (adaptive)")
    parser.add_argument(
        "--sawtooth", nargs="*", type=int, help="FIRST LAST pair count of the sawtooth (none: off)"
    )
    parser.add_argument("--tolerance", type=float, help="tolerance of the adaptive runs")
    parser.add_argument("--no-figures", action="store_true")
    parser.add_argument("--page", help="also write the results page (markdown) from the study")
    parser.add_argument(
        "--benchmarks", nargs="*", default=(), help="performance.py --json files for the page"
    )
    return parser


def main(argv=None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.sawtooth and len(args.sawtooth) != 2:
        parser.error("--sawtooth takes two pair counts, FIRST LAST (or none to skip it)")
    plan = StudyPlan.quick() if args.quick else StudyPlan.full()
    tuples = lambda values: None if values is None else tuple(values)  # noqa: E731
    changes = {
        "families": tuples(args.families),
        "pairs": tuples(args.pairs),
        "large_pairs": tuples(args.large_pairs),
        "rest_pairs": tuples(args.rest_pairs),
        "rest_factors": tuples(args.rest_factors),
        "repeats": args.repeats,
        "memory": False if args.no_memory else None,
        "adaptive_families": tuples(args.adaptive_families),
        "budgets": tuples(args.budgets),
        "sawtooth": tuples(args.sawtooth),
        "tolerance": args.tolerance,
    }
    plan = attrs.evolve(plan, **{k: v for k, v in changes.items() if v is not None})
    print(f"{os.cpu_count()} cores; plan: {attrs.asdict(plan)}")
    run_study(plan, args.out, figures=not args.no_figures)
    if args.page:
        # the page generator is documentation tooling, beside the Sphinx extensions
        sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "docs" / "sphinxext"))
        from results_page_text import write_results_page

        page = write_results_page(
            Path(args.out) / CSV_NAME,
            args.page,
            figure_dir=args.out,
            benchmarks=args.benchmarks,
        )
        print(f"wrote {page}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
