"""The demo's three PNGs written by two trees' figure code in one process (issue 28 item 4).

``fretbem.output.figures`` (with its canvas and PNG writer) of ``--before DIR`` and of this
checkout write the demo's tractions, displacements and pair-state PNGs (nurbs, lagrange2 and
lagrange3 at 61 pairs, solved once by this checkout) alternately, ``--rounds`` times; each
round empties both canvases' tables of kept texts, as a fresh demo process starts. CPU
seconds of ``save_figures`` are printed (medians, and the median of the per-round ratios);
a first round of each tree warms matplotlib's caches and is dropped. Both trees run in the
same process under the same load, so the ratio holds on a busy machine where the
fresh-process row of ``workflows.py --only demo`` moves by 20 %::

    git archive <commit> | tar -x -C /tmp/before
    OPENBLAS_NUM_THREADS=1 python benchmarks/figures_trees.py --before /tmp/before --rounds 11
"""

from __future__ import annotations

import gc
import importlib
import os
import sys
import tempfile
import time
import types
from pathlib import Path

from canvas_text import demo_results, forget_texts, options, summary

ROOT = Path(__file__).resolve().parents[1]


def _figure_modules(tree: Path, name: str):
    """``tree``'s figures and canvas modules, imported as the package ``name`` (their relative
    imports resolve inside it; their imports of fretbem to the fretbem already imported)."""
    package = types.ModuleType(name)
    package.__path__ = [str(tree / "framework" / "fretbem" / "output")]
    sys.modules[name] = package
    return importlib.import_module(f"{name}.figures"), importlib.import_module(f"{name}.canvas")


def main(argv: list[str] | None = None) -> dict:
    args = options(__doc__.split("\n\n")[0], 11, argv)
    results = demo_results()  # fretbem imported before the trees' figure modules
    trees = {"before": _figure_modules(args.before, "figures_before"),
             "after": _figure_modules(ROOT, "figures_after")}  # fmt: skip

    def written(figures, canvas, directory: str) -> float:
        forget_texts(canvas)
        start = time.process_time()
        figures.save_figures(results, directory)
        spent = time.process_time() - start
        gc.collect()  # the figures' cycles, between the timed calls
        return spent

    times: dict[str, list[float]] = {name: [] for name in trees}
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.rounds + 1):
            for name, (figures, canvas) in trees.items():
                times[name].append(written(figures, canvas, f"{tmp}/{name}"))
    load.append(os.getloadavg()[0])
    return summary(times, load, args.rounds, "the demo's three PNGs")


if __name__ == "__main__":
    main()
