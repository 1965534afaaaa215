"""What a coarser 3D grid buys in time and costs in accuracy (issue 28, item 1).

The 3D critical-plane search (four criteria, the workflows benchmark's 10,000 points) was
4.2-6x the projection floor of its 5 x 10 degree grid against a limit of 3, and
``benchmarks/fatigue_3d_layouts.py`` found the per-plane loops near what numba makes of them.
This script measures the remaining lever, fewer planes, in one process:

- time: the compiled search at each ``--grids`` entry (theta step / psi step / refinement
  levels, degrees) over the projection floor of the default 5 x 10 degree grid (the floor of
  ``benchmarks/fatigue_phases.py --before``), interleaved, least of ``--runs``; and the same
  search over the floor of its own grid;
- accuracy: every criterion (stress_life also with Goodman and Gerber corrections) on contact
  cycles (Cattaneo-Mindlin / Nowell-Hills at Q/fP 0.3, 0.5, 0.8 and bulk 0, 80, 150 MPa, and
  :func:`fretbem.testing.fatigue.contact_stress_history` at three depths), random plane-strain
  histories and random histories with a free sigma_zz (``--points`` each) against a dense
  reference ten times finer than the default grid (0.5 x 1 degree, 10 refinement levels):
  the largest shortfall (reference - found) over the history's largest reference value, and
  the shortfall of the history's hot spot (the largest value over its points).

Measured on 2026-11-27 (load 4, least of 21; the floor 17-21 ms from run to run): the
search's refinement and per-point work alone (a 4-plane grid, 60/90/5) are 2.4x the floor,
so no grid with five levels meets 3x robustly (5/10/5 4.8-6.0x, 10/15/5 3.4x, 10/30/5 3.0x,
5/45/5 3.0-3.5x); 5/45/3, the default since, 2.4-2.9x (5/45/4 3.2x, 5/45/2 2.2x). A 10 degree
theta step misses second maxima on contact cycles (Findley 7.0e-3 of the largest value
against 1.6e-3); psi rows 90 and 45 degrees keep every contact cycle's shortfall of the
5 x 10 grid (the psi rows in between never win there) and on random histories with a free
sigma_zz lose more to second maxima (Findley 3.7e-3 -> 6.7e-3) and less (MWCM 3.1e-3 ->
6e-11); psi rows 90, 60, 30 (5/30/5) lose MWCM 4.9e-2 there; 90 alone (5/90/5) 8.6e-2.

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_3d_grid_study.py
    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_3d_grid_study.py --grids 5/10/5 10/15/5 \
        --runs 21 --points 60
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from fatigue_accuracy import KW, free_history
from fatigue_phases import captured_arguments, floor_of, least_cpu, stress_cycle

from fretbem.fatigue import (
    METHODS,
    CattaneoMindlinCycle,
    PlaneSearch,
    critical_plane_parameters,
    last_full_reversal,
)
from fretbem.fatigue import compiled_search as cs
from fretbem.fatigue.mean_stress import MeanStressCorrection
from fretbem.fatigue.planes import plane_grid
from fretbem.testing.fatigue import contact_stress_history, random_stress_history

#: theta step / psi step / refinement levels: the default, coarser psi, coarser theta, and a
#: 4-plane grid whose time is the refinement's and the per-point work's alone
GRIDS = ["5/10/5", "5/15/5", "5/45/5", "5/90/5", "10/15/5", "10/30/5", "15/15/5", "60/90/5"]
DENSE = PlaneSearch(theta_step_deg=0.5, psi_step_deg=1.0, refine_levels=10, compiled=True)
CORRECTIONS = {
    "none": None,
    "goodman": MeanStressCorrection(name="goodman", limit=900.0),
    "gerber": MeanStressCorrection(name="gerber", limit=900.0),
}


def parse_grid(text: str) -> PlaneSearch:
    theta, psi, levels = text.split("/")
    return PlaneSearch(theta_step_deg=float(theta), psi_step_deg=float(psi),
                       refine_levels=int(levels), compiled=True)  # fmt: skip


def timing(grids: list[str], runs: int) -> None:
    stress = stress_cycle()
    fns = {"floor 5/10": floor_of(stress, False, 5.0, 10.0)}
    for text in grids:
        search = parse_grid(text)
        args = captured_arguments(stress, search)
        fns[text] = lambda a=args: cs.search(*a)
        fns[f"floor {text}"] = floor_of(stress, False, search.theta_step_deg, search.psi_step_deg)
    low = least_cpu(fns, runs)
    print(f"3D, four criteria, 10,000 points: floor of the 5 x 10 grid "
          f"{low['floor 5/10'] * 1e3:.1f} ms")  # fmt: skip
    print(f"{'grid':<10}{'planes':>7}{'search ms':>11}{'/ 5x10 floor':>14}{'/ own floor':>13}")
    for text in grids:
        search = parse_grid(text)
        theta, _ = plane_grid(in_plane_only=False, theta_step_deg=search.theta_step_deg,
                              psi_step_deg=search.psi_step_deg)  # fmt: skip
        print(
            f"{text:<10}{theta.size:>7}{low[text] * 1e3:>11.1f}"
            f"{low[text] / low['floor 5/10']:>14.2f}{low[text] / low[f'floor {text}']:>13.2f}"
        )


def histories(n: int) -> dict[str, np.ndarray]:
    out = {}
    rng = np.random.default_rng(11)
    points = np.stack([rng.uniform(-0.75, 0.75, n), rng.uniform(0.0, 0.5, n)], axis=1)
    for q, bulk in ((0.3, 0.0), (0.5, 80.0), (0.8, 150.0)):
        cm = CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=q,
                                  sigma_bulk_max=bulk, nu=0.342, steps_per_branch=2)  # fmt: skip
        out[f"contact Q/fP {q} bulk {bulk:.0f}"] = cm.stress_at(points)[
            last_full_reversal(cm.driver)
        ]
    for depth, steps in ((0.3, 3), (0.5, 2), (1.0, 4)):
        out[f"contact depth {depth}"] = contact_stress_history(
            n, 11, depth=depth, steps_per_branch=steps, nu=0.342
        )
    out["random plane strain"] = random_stress_history(n, 5, nu=0.342)
    out["free szz"] = free_history(n, 7)
    return out


def accuracy(grids: list[str], points: int) -> None:
    worst: dict = {}
    for name, stress in histories(points).items():
        kind = "contact" if name.startswith("contact") else name
        for label, correction in CORRECTIONS.items():
            methods = METHODS if correction is None else ("stress_life",)
            ref = critical_plane_parameters(stress, methods=methods, mean_stress=correction,
                                            search=DENSE, **KW)  # fmt: skip
            for text in grids:
                got = critical_plane_parameters(stress, methods=methods, mean_stress=correction,
                                                search=parse_grid(text), **KW)  # fmt: skip
                for method in methods:
                    r, g = ref[method].value, got[method].value
                    finite = np.isfinite(r) & np.isfinite(g)
                    scale = np.abs(r[finite]).max(initial=1e-300)
                    gap = (r[finite] - g[finite]) / scale
                    hot = (r[finite].max(initial=0.0) - g[finite].max(initial=0.0)) / scale
                    row = method if correction is None else f"{method} {label}"
                    w = worst.setdefault((text, kind, row), [0.0, 0.0, 0])
                    w[0] = max(w[0], gap.max(initial=0.0))
                    w[1] = max(w[1], hot)
                    w[2] += int((np.isfinite(r) != np.isfinite(g)).sum())
        print(f"done: {name}", flush=True)
    print(f"{'grid':<10}{'histories':<20}{'criterion':<22}{'shortfall':>11}{'hot spot':>11}"
          f"{'inf differs':>12}")  # fmt: skip
    for (text, kind, row), (short, hot, inf) in worst.items():
        print(f"{text:<10}{kind:<20}{row:<22}{short:11.2e}{hot:11.2e}{inf:12d}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=GRIDS)
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--points", type=int, default=120, help="points per history")
    parser.add_argument("--skip", choices=["time", "accuracy"], help="leave one part out")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}")
    if args.skip != "time":
        timing(args.grids, args.runs)
    if args.skip != "accuracy":
        accuracy(args.grids, args.points)


if __name__ == "__main__":
    main()
