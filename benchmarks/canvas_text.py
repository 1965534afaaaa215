"""The demo's three figures drawn on two trees' figure canvases in one process (issue 28 item 4).

``fretbem.output.canvas`` of ``--before DIR`` and of this checkout draw the same figures
(the demo's tractions, displacements and pair states of nurbs, lagrange2 and lagrange3 at
61 pairs, unhinted text as the demo draws it) alternately, ``--rounds`` times; each round
starts with empty glyph-layout and text-image tables, as a demo process does. CPU seconds
of the draws (``savefig`` to raw RGBA) are printed, medians and the per-round ratio; the
first round warms matplotlib's caches and is dropped::

    git archive <commit> | tar -x -C /tmp/before
    OPENBLAS_NUM_THREADS=1 python benchmarks/canvas_text.py --before /tmp/before --rounds 15
"""

from __future__ import annotations

import argparse
import io
import os
import statistics
import sys
import time
from pathlib import Path

from tree_module import tree_module

ROOT = Path(__file__).resolve().parents[1]
#: the tables of kept texts a tree's canvas may have (each round starts with them empty)
TABLES = ("_LAYOUTS", "_TEXTS", "_GLYPHS")


def forget_texts(canvas) -> None:
    """Empty the canvas module's tables of kept texts (those the tree has)."""
    for table in TABLES:
        getattr(canvas, table, {}).clear()


def options(description: str, rounds: int, argv: list[str] | None) -> argparse.Namespace:
    """--before (the old tree) and --rounds, with this checkout's framework and plugins put
    first on the path (the figure benchmarks import fretbem from here)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--before", type=Path, required=True, help="source tree of the old code")
    parser.add_argument("--rounds", type=int, default=rounds)
    args = parser.parse_args(argv)
    sys.path[:0] = [str(ROOT / "framework"), str(ROOT / "plugins")]
    return args


def demo_results() -> list:
    """What the demo draws: the reference cycle of nurbs, lagrange2 and lagrange3, 61 pairs."""
    from fretbem.scenes.reference import cattaneo_mindlin
    from fretbem.simulation import run

    return [run(cattaneo_mindlin(basis=b, pairs=61)) for b in ("nurbs", "lagrange2", "lagrange3")]


def summary(times: dict, load: list, rounds: int, what: str) -> dict:
    """Print and return each tree's median CPU seconds and the median after / before ratio
    per round, the first (warm-up) round dropped."""
    out = {name: statistics.median(values[1:]) for name, values in times.items()}
    ratios = [a / b for a, b in zip(times["after"][1:], times["before"][1:], strict=True)]
    out["after / before, per round"] = statistics.median(ratios)
    print(f"{what}, CPU s (median of {rounds}; load {min(load):.1f}-{max(load):.1f}): before "
          f"{out['before']:.3f}, after {out['after']:.3f}, after / before per round "
          f"{out['after / before, per round']:.3f}")  # fmt: skip
    return out


def _canvas_module(tree: Path, name: str):
    return tree_module(tree, "fretbem.output.canvas", name)


def main(argv: list[str] | None = None) -> dict:
    args = options(__doc__.split("\n\n")[0], 15, argv)
    import matplotlib

    from fretbem.output import figures

    canvases = {"before": _canvas_module(args.before, "canvas_before"),
                "after": _canvas_module(ROOT, "canvas_after")}  # fmt: skip
    results = demo_results()
    makers = (figures.traction_figure, figures.displacement_figure, figures.stick_slip_figure)

    def drawn(module) -> float:
        forget_texts(module)
        spent = 0.0
        with matplotlib.rc_context({"text.hinting": "no_hinting"}):
            for make in makers:
                fig = make(results)
                module.FigureCanvas(fig)
                figures._ticks_in_view(fig)
                start = time.process_time()
                fig.savefig(io.BytesIO(), dpi=figures.DPI, format="rgba")
                spent += time.process_time() - start
        return spent

    times: dict[str, list[float]] = {name: [] for name in canvases}
    load = [os.getloadavg()[0]]
    for _ in range(args.rounds + 1):
        for name, module in canvases.items():
            times[name].append(drawn(module))
    load.append(os.getloadavg()[0])
    return summary(times, load, args.rounds, "draws of the three figures")


if __name__ == "__main__":
    main()
