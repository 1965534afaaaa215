"""Generate docs/results.md (and its three figures) from the convergence study's CSVs.

Every number on the page is computed from convergence.csv and, next to it, study.json (the
machine), adaptive_study.csv (the adaptive mode's budget series) and
adaptive_study_sawtooth.csv (both modes at every pair count); the figures are redrawn into
``--figures`` (default: a folder named after the page, e.g. docs/results/). Benchmark
medians from ``benchmarks/performance.py --json`` are added as a table when given.

    python benchmarks/results_page.py --csv docs/results/convergence.csv --out docs/results.md \\
        --benchmarks docs/results/benchmarks-1thread.json docs/results/benchmarks-default.json

Study and page in one command (one BLAS thread, as the page says)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/convergence_study.py --out docs/results \\
        --page docs/results.md \\
        --benchmarks docs/results/benchmarks-1thread.json docs/results/benchmarks-default.json

The benchmark files themselves::

    OPENBLAS_NUM_THREADS=1 python benchmarks/performance.py \\
        --json docs/results/benchmarks-1thread.json
    python benchmarks/performance.py --only cycle demo steps \\
        --json docs/results/benchmarks-default.json
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

# the page generator is documentation tooling, beside the Sphinx extensions
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "docs" / "sphinxext"))
from results_page_text import write_results_page


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--csv", required=True, help="convergence.csv of `fretbem convergence` (the others beside)"
    )
    parser.add_argument("--out", default="docs/results.md", help="markdown page to write")
    parser.add_argument("--figures", help="folder for the PNG figures (default: next to --out)")
    parser.add_argument(
        "--benchmarks",
        nargs="*",
        default=(),
        help="JSON files written by benchmarks/performance.py --json (one column each)",
    )
    args = parser.parse_args(argv)
    path = write_results_page(
        args.csv, args.out, figure_dir=args.figures, benchmarks=args.benchmarks
    )
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
