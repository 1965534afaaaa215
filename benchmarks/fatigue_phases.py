"""Where the compiled critical-plane search spends its time, phase by phase, against its floor.

The workflows benchmark's fatigue case (10,000 points below a Cattaneo-Mindlin contact, the
last full reversal, all four critical-plane criteria), timed in one process as ratios to the
projection floor (one float32 product per chunk, as ``benchmarks/workflows.py``): the coarse
grid's step summaries alone (point by point), the whole coarse grid (summaries, bounds,
circles, the best plane of each criterion; in-plane by blocks of points, as the search),
the search with 0..``refine_levels`` refinement levels (level 0: one pattern level and the
parabolic step), and the whole ``critical_plane_parameters`` call.
Medians of ``--runs`` CPU times; run it alone (the machine is shared: ratios, not seconds).

``--before DIR``: instead, the compiled search of another source tree (``git archive <commit>
| tar -x -C DIR``) against this tree's, interleaved run by run in one process against one
floor; the least CPU time of ``--runs`` each (the other tree's module is compiled afresh,
without numba's cache); ``--methods`` the criteria searched there. The other tree searches
with the defaults before issue 28's 3D grid change (``FORMER``: psi every 10 degrees, five
levels; in-plane the same search), this tree with its own; ``--same-grid``: the other tree with
this tree's defaults too (a tree from after the grid change: the code's change alone).

The floor is always the projection of the 5 x 10 degree grid (``FLOOR_GRID``, 325 planes in
3D): the issue's floor, and the search the default 3D grid (73 planes, three levels) was
checked against for accuracy (``benchmarks/fatigue_3d_grid_study.py``). Against the
projection of its own 73 planes the default 3D search is ~12x (that study prints both).

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_phases.py --runs 7
    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_phases.py --before /tmp/before --runs 21
    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_phases.py --before /tmp/before \
        --methods strain_life stress_life
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import types
from pathlib import Path

import numba
import numpy as np

from fretbem.fatigue import (
    METHODS,
    CattaneoMindlinCycle,
    PlaneSearch,
    critical_plane_parameters,
    last_full_reversal,
)
from fretbem.fatigue import compiled_search as cs
from fretbem.fatigue.planes import plane_grid, projection

CONSTANTS = {"findley_k": 0.3, "fatemi_socie_k": 0.5, "yield_strength": 941.8}
#: theta and psi steps (degrees) of the projection floor
FLOOR_GRID = (5.0, 10.0)
#: the 3D search's settings before issue 28's grid change (in-plane: unchanged)
FORMER = {"psi_step_deg": 10.0, "refine_levels": 5}


def stress_cycle() -> np.ndarray:
    """(9, 10,000, 4): the workflows benchmark's fatigue history."""
    cm = CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5,
                              sigma_bulk_max=80.0, nu=0.342, steps_per_branch=2)  # fmt: skip
    X, Z = np.meshgrid(np.linspace(-0.75, 0.75, 100), np.linspace(0.0, 0.5, 100))
    stress = cm.stress_at(np.stack([X.ravel(), Z.ravel()], axis=1))
    return stress[last_full_reversal(cm.driver)]


@numba.njit
def _coarse_phase(stress, grid, axes, rank, codes, par, nu, E, in_plane, whole):
    """The coarse grid over every point: its summaries alone, or (``whole``) all of it; by
    blocks of points as the search (in-plane summaries alone: point by point)."""
    n_t, n_p, n_g = stress.shape[0], stress.shape[1], grid.shape[1]
    nb_max = min(cs.BLOCK, n_p)
    block = np.empty((5, n_t, nb_max))
    m, h, xy, zz, tr = block[0], block[1], block[2], block[3], block[4]
    data = (m, h, xy, zz, tr, np.empty(n_t), np.empty(n_t))
    size = max(n_g, 1)
    work = (np.empty((12, size)), np.empty(size), np.empty(size), np.empty(size),
            np.empty(size), np.empty(size), np.empty(size), np.empty(size, dtype=np.bool_),
            np.empty(size, dtype=np.int64))  # fmt: skip
    scratch = (np.empty((6, axes[0].size), dtype=np.float32),
               np.empty((12, size), dtype=np.float32))  # fmt: skip
    axes = (axes[0].astype(np.float32), axes[1].astype(np.float32),
            axes[2].astype(np.float32), axes[3].astype(np.float32))  # fmt: skip
    best = np.empty(codes.size * nb_max, dtype=np.int64)
    found = np.empty((7, codes.size * nb_max))
    sup = np.empty(3, dtype=np.int64)
    total = 0.0
    for p0 in range(0, n_p, nb_max):
        nb = min(nb_max, n_p - p0)
        for t in range(n_t):
            for b in range(nb):
                sxx, syy = stress[t, p0 + b, 0], stress[t, p0 + b, 1]
                m[t, b], h[t, b] = 0.5 * (sxx + syy), 0.5 * (sxx - syy)
                xy[t, b], zz[t, b] = stress[t, p0 + b, 2], stress[t, p0 + b, 3]
                tr[t, b] = 2.0 * m[t, b] + zz[t, b]
        if in_plane and whole:  # cs._coarse_in_plane
            cs._coarse_in_plane(m, h, xy, tr, 0, nb, nu, grid[0], grid[1], codes, par, E,
                                best, found)  # fmt: skip
            total += found[0, 0]
        elif in_plane:
            for b in range(nb):
                cs._grid_summaries(m, h, xy, zz, tr, b, nu, grid[0], grid[1], axes, in_plane,
                                   work[0], scratch)  # fmt: skip
                total += work[0][0, 0]
        else:  # cs._coarse_3d, its summaries alone unless whole
            cs._coarse_3d(data, nb, grid, axes, rank, codes, par, nu, E, work, scratch, best,
                          found, sup, whole)  # fmt: skip
            total += found[0, 0] if whole else scratch[1][0, 0]
    return total


def median_cpu(fn, runs: int) -> float:
    fn()
    times = []
    for _ in range(runs):
        start = time.process_time()
        fn()
        times.append(time.process_time() - start)
    return statistics.median(times)


def phases(stress: np.ndarray, in_plane: bool, runs: int) -> None:
    """Print each phase's median CPU time over the floor's, in-plane or 3D."""
    search = PlaneSearch(in_plane_only=in_plane, compiled=True)
    floor = floor_of(stress, in_plane, chunk=search.chunk_points)

    def whole():
        critical_plane_parameters(stress, E=116000.0, nu=0.342, methods=METHODS[:4],
                                  search=search, **CONSTANTS)  # fmt: skip

    a = captured_arguments(stress, search)
    grid, axes, rank, codes, par, nu, E = a[1], a[2], a[3], a[6], a[7], a[8], a[9]
    t_floor = median_cpu(floor, runs)
    rows = {
        "coarse summaries": lambda: _coarse_phase(
            a[0], grid, axes, rank, codes, par, nu, E, in_plane, False
        ),
        "coarse grid": lambda: _coarse_phase(
            a[0], grid, axes, rank, codes, par, nu, E, in_plane, True
        ),
    }
    for levels in range(search.refine_levels + 1):
        rows[f"search, {levels} levels"] = lambda levels=levels: cs.search(*a[:11], levels, a[12])
    rows["critical_plane_parameters"] = whole
    print(f"{'in-plane' if in_plane else '3D'}: floor {t_floor * 1e3:.1f} ms")
    for name, fn in rows.items():
        print(f"  {name:<28s} {median_cpu(fn, runs) / t_floor:6.2f} x floor")


def floor_of(stress: np.ndarray, in_plane: bool, theta_deg: float = FLOOR_GRID[0],
             psi_deg: float = FLOOR_GRID[1], chunk: int = 400):  # fmt: skip
    """The projection floor of a grid: every (step, point, plane) in one float32 product per
    chunk of points.

    Into buffers allocated once (the float32 copy, a chunk's product), as in the workflows
    benchmark: a fresh array per call read the allocator's state, not the product (in half
    the fresh processes glibc gave the in-plane floor's copy and products fresh pages, ~700
    page faults a call, 2.45 ms against 1.40 ms)."""
    theta, psi = plane_grid(in_plane_only=in_plane, theta_step_deg=theta_deg,
                            psi_step_deg=psi_deg)  # fmt: skip
    coef = projection(theta, psi).astype(np.float32).transpose(2, 0, 1).reshape(4, -1)
    s32 = np.empty(stress.shape, dtype=np.float32)
    out = np.empty((stress.shape[0], chunk, coef.shape[1]), dtype=np.float32)

    def floor():
        np.copyto(s32, stress, casting="same_kind")
        for a in range(0, s32.shape[1], chunk):
            part = s32[:, a : a + chunk]
            np.matmul(part, coef, out=out[:, : part.shape[1]])

    return floor


def captured_arguments(stress: np.ndarray, search: PlaneSearch, methods=METHODS[:4]) -> tuple:
    """The arguments ``critical_plane_parameters`` hands to the compiled search with
    ``search``."""
    captured = {}
    real = cs.search

    def spy(*a):
        captured["args"] = a
        return real(*a)

    cs.search = spy
    try:
        critical_plane_parameters(stress, E=116000.0, nu=0.342, methods=methods,
                                  search=search, **CONSTANTS)  # fmt: skip
    finally:
        cs.search = real
    return captured["args"]


def search_arguments(stress: np.ndarray, in_plane: bool, methods=METHODS[:4], **settings) -> tuple:
    """The compiled search's arguments (``settings``: of :class:`PlaneSearch`, the defaults
    otherwise)."""
    search = PlaneSearch(in_plane_only=in_plane, compiled=True, **settings)
    return captured_arguments(stress, search, methods)


def least_cpu(fns: dict, runs: int) -> dict:
    """Each function's least CPU time of ``runs``, interleaved run by run after one warm-up."""
    times = {k: [] for k in fns}
    for fn in fns.values():
        fn()
    for _ in range(runs):
        for key, fn in fns.items():
            start = time.process_time()
            fn()
            times[key].append(time.process_time() - start)
    return {k: min(v) for k, v in times.items()}


def against_tree(
    stress: np.ndarray, before: Path, runs: int, methods=METHODS[:4], same_grid: bool = False
) -> None:
    """This tree's compiled search and ``before``'s over the floor, interleaved, least times."""
    text = (before / "framework/fretbem/fatigue/compiled_search.py").read_text()
    old = types.ModuleType("compiled_search_before")
    exec(compile(text.replace('"cache": True', '"cache": False'), "before", "exec"), old.__dict__)
    for in_plane in (True, False):
        a = search_arguments(stress, in_plane, methods)
        b = search_arguments(stress, in_plane, methods, **({} if in_plane or same_grid else FORMER))
        fns = {"floor": floor_of(stress, in_plane), "before": lambda b=b: old.search(*b),
               "after": lambda a=a: cs.search(*a)}  # fmt: skip
        low = least_cpu(fns, runs)
        print(f"{'in-plane' if in_plane else '3D'}: floor {low['floor'] * 1e3:.1f} ms, search "
              f"before {low['before'] / low['floor']:.2f} x floor, after "
              f"{low['after'] / low['floor']:.2f} x floor")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--before", type=Path, help="another source tree: before/after")
    parser.add_argument(
        "--methods",
        nargs="+",
        default=list(METHODS[:4]),
        choices=METHODS,
        help="the criteria of --before (default: the four critical-plane ones)",
    )
    parser.add_argument(
        "--same-grid",
        action="store_true",
        help="the --before tree searches this tree's default grid too (not the former one)",
    )
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}")
    stress = stress_cycle()
    if args.before:
        against_tree(stress, args.before, args.runs, tuple(args.methods), args.same_grid)
        return
    for in_plane in (True, False):
        phases(stress, in_plane, args.runs)


if __name__ == "__main__":
    main()
