"""Figure time of the reference cycle against its solve time (issue 10: figures well under).

Runs the demo's two families once, then draws the figures ``--repeat`` times into a temporary
directory; the first call includes matplotlib's import (fretbem.output.figures
loads it on first use),
the median is over the later calls. Usage: python benchmarks/figures.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time


def main(repeat: int) -> dict:
    from fretbem.scenes.reference import cattaneo_mindlin
    from fretbem.simulation import run

    solves, results = [], []
    for basis in ("nurbs", "lagrange2"):
        start = time.perf_counter()
        results.append(run(cattaneo_mindlin(basis=basis, pairs=61)))
        solves.append(time.perf_counter() - start)
    start = time.perf_counter()
    from fretbem.output import figures as plot

    imports = time.perf_counter() - start
    figures = []
    for _ in range(repeat + 1):
        with tempfile.TemporaryDirectory() as directory:
            start = time.perf_counter()
            plot.save_figures(results, directory)
            figures.append(time.perf_counter() - start)
    out = {
        "solve_nurbs_s": round(solves[0], 3),
        "solve_lagrange2_s": round(solves[1], 3),
        "import_plot_s": round(imports, 3),
        "figures_first_call_s": round(figures[0], 3),
        "figures_median_s": round(statistics.median(figures[1:]), 3),
        "figures_runs": [round(f, 3) for f in figures[1:]],
    }
    print(out)
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    main(parser.parse_args().repeat)
