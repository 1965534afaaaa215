"""A study: where the 3D critical-plane search's time goes, and loop layouts that did not pay.

Not a change to the search (:mod:`fretbem.fatigue.compiled_search`): what was measured on the
workflows benchmark's 10,000 points (``benchmarks/fatigue_phases.py``, four criteria, 3D,
issue 28 item 1: the limit is 3x the projection floor, the search is 6.1-6.5x), kept so that
the next attempt starts from it. Whole-search ratios to the floor, in one process, least of
21 interleaved runs (load 2.4), each variant a copy of the module with one change:

- the search as it is: 6.53x; with its refinement's plane summaries replaced by a constant
  (a timing stub): 3.73 against 5.17x in that run, so the refinement's ~100 plane
  evaluations per point (4 criteria: the start plane again in double, 4 neighbours a level,
  6 levels, the parabolic step) cost ~1.4x the floor in their summaries alone; the coarse
  grid's summaries ~1.1x, its per-criterion passes (values, bounds, best plane) ~1.4-1.7x;
  exact circles almost nothing (0.0009 per point on the grid; ~3 % of the search in the
  refinement);
- the refinement's plane summaries by blocks of points, one loop per pair of extremes over
  the block's 64 points (vectorised: ``vcmpgtpd``): 6.66x (the round-off of the values
  moves, 4e-16); in isolation (below) slower than point by point with the extremes in
  registers;
- the grid's reductions (largest value, best lower bound, first plane by rank, the MWCM
  ties) with eight running extremes instead of one (bit-identical; below, ~2.5x faster
  alone on 325 planes): 6.69x;
- each criterion's grid passes fused into one (values, bounds, the best lower bound and the
  largest open bound together; bit-identical): 6.78x;
- the grid summaries' rows of psi as four loops of one pair of extremes each: 6.86x; as
  linear forms of (m, h, sxy, szz) over all 324 tilted planes at once (long loops,
  bit-identical choices here): summaries 1.18 -> 1.51x the floor.

So the per-plane loops are already near what numba makes of them: the 3x needs fewer plane
evaluations (a coarser grid with bounds that rule out whole blocks of planes, fewer
refinement levels or a refinement that needs fewer neighbours), not a different loop layout.
What this script times: the two refinement layouts and the two reductions, in one process.

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_3d_layouts.py
"""

from __future__ import annotations

import argparse
import os
import time

import numba
import numpy as np

from fretbem.fatigue import compiled_search as cs

_LOOPS = {"nogil": True, "error_model": "numpy", "fastmath": {"nnan", "contract", "nsz"}}


@numba.njit(**_LOOPS)
def block_summaries(m, h, xy, zz, tr, nb, nu, c2, s2, sp, cp, start, out):
    """The 3D plane summaries of planes ``start:start + nb`` (plane ``start + b`` of point b),
    step by step over the points: one vectorised loop per pair of extremes."""
    a = 1.0 + nu
    stop = start + nb
    rows = [out[r, start:stop] for r in range(12)]
    c, s, q, k = c2[start:stop], s2[start:stop], sp[start:stop], cp[start:stop]
    for r in range(12):
        rows[r][:] = -np.inf if r % 2 == 0 else np.inf
    o0, o1, o2, o3, o4, o5 = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    o6, o7, o8, o9, o10, o11 = rows[6], rows[7], rows[8], rows[9], rows[10], rows[11]
    for t in range(m.shape[0]):
        mt, ht, xyt, zzt, trt = m[t], h[t], xy[t], zz[t], tr[t]
        for b in range(nb):
            sn = (q[b] * q[b]) * (mt[b] + ht[b] * c[b] + xyt[b] * s[b]) + (k[b] * k[b]) * zzt[b]
            o0[b] = sn if sn > o0[b] else o0[b]
            o1[b] = sn if sn < o1[b] else o1[b]
        for b in range(nb):
            sn = (q[b] * q[b]) * (mt[b] + ht[b] * c[b] + xyt[b] * s[b]) + (k[b] * k[b]) * zzt[b]
            en = a * sn - nu * trt[b]
            o2[b] = en if en > o2[b] else o2[b]
            o3[b] = en if en < o3[b] else o3[b]
        for b in range(nb):
            px = (q[b] * k[b]) * (mt[b] + ht[b] * c[b] + xyt[b] * s[b] - zzt[b])
            o4[b] = px if px > o4[b] else o4[b]
            o5[b] = px if px < o5[b] else o5[b]
        for b in range(nb):
            py = q[b] * (xyt[b] * c[b] - ht[b] * s[b])
            o6[b] = py if py > o6[b] else o6[b]
            o7[b] = py if py < o7[b] else o7[b]
        for b in range(nb):
            u = (q[b] * k[b]) * (mt[b] + ht[b] * c[b] + xyt[b] * s[b] - zzt[b]) + q[b] * (
                xyt[b] * c[b] - ht[b] * s[b]
            )
            o8[b] = u if u > o8[b] else o8[b]
            o9[b] = u if u < o9[b] else o9[b]
        for b in range(nb):
            v = (q[b] * k[b]) * (mt[b] + ht[b] * c[b] + xyt[b] * s[b] - zzt[b]) - q[b] * (
                xyt[b] * c[b] - ht[b] * s[b]
            )
            o10[b] = v if v > o10[b] else o10[b]
            o11[b] = v if v < o11[b] else o11[b]


@numba.njit(**_LOOPS)
def by_blocks(reps, n_rep, nb, m, h, xy, zz, tr, c2, s2, sp, cp, out):
    for _ in range(reps):
        for r in range(n_rep):
            block_summaries(m, h, xy, zz, tr, nb, 0.342, c2, s2, sp, cp, r * nb, out)


@numba.njit(**_LOOPS)
def by_points(reps, n_rep, nb, m, h, xy, zz, tr, c2, s2, sp, cp, out):
    """As the search: point by point, the extremes over the steps in registers."""
    for _ in range(reps):
        for r in range(n_rep):
            for b in range(nb):
                g = r * nb + b
                cs._plane_summaries_3d(m, h, xy, zz, tr, b, 0.342, c2[g], s2[g], sp[g], cp[g],
                                       True, out, g)  # fmt: skip


@numba.njit(**_LOOPS)
def one_max(reps, value):
    total = 0.0
    for _ in range(reps):
        top = -np.inf
        for g in range(value.size):
            top = max(top, value[g])
        total += top
    return total


@numba.njit(**_LOOPS)
def eight_max(reps, value):
    total = 0.0
    n = value.size
    n8 = n - n % 8
    for _ in range(reps):
        a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = -np.inf
        for g in range(0, n8, 8):
            a0, a1, a2, a3 = max(a0, value[g]), max(a1, value[g + 1]), \
                max(a2, value[g + 2]), max(a3, value[g + 3])  # fmt: skip
            a4, a5, a6, a7 = max(a4, value[g + 4]), max(a5, value[g + 5]), \
                max(a6, value[g + 6]), max(a7, value[g + 7])  # fmt: skip
        top = max(max(max(a0, a1), max(a2, a3)), max(max(a4, a5), max(a6, a7)))
        for g in range(n8, n):
            top = max(top, value[g])
        total += top
    return total


def least(fn, runs: int) -> float:
    fn()
    times = []
    for _ in range(runs):
        start = time.process_time()
        fn()
        times.append(time.process_time() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}")
    rng = np.random.default_rng(0)
    n_t, nb, n_rep, reps = 9, cs.BLOCK, 16, 300
    m, h, xy, zz, tr = (rng.normal(size=(n_t, nb)) * 100.0 for _ in range(5))
    theta, psi = rng.random(n_rep * nb) * np.pi, rng.random(n_rep * nb) * 0.5 * np.pi
    planes = (np.cos(2 * theta), np.sin(2 * theta), np.sin(psi), np.cos(psi))
    a, b = np.empty((12, n_rep * nb)), np.empty((12, n_rep * nb))
    by_points(1, n_rep, nb, m, h, xy, zz, tr, *planes, a)
    by_blocks(1, n_rep, nb, m, h, xy, zz, tr, *planes, b)
    print(f"  the two layouts agree to {np.abs(a - b).max() / np.abs(a).max():.1e}")
    for name, fn in (
        ("point by point (the search)", by_points),
        ("by blocks, vectorised", by_blocks),
    ):
        t = least(lambda fn=fn: fn(reps, n_rep, nb, m, h, xy, zz, tr, *planes, a), args.runs)
        print(
            f"  refinement summaries, {name:<28s} {t / reps / (n_rep * nb) * 1e9:6.1f} ns a plane"
        )
    value = rng.normal(size=325)
    assert one_max(1, value) == eight_max(1, value)
    for name, fn in (("one running maximum", one_max), ("eight running maxima", eight_max)):
        t = least(lambda fn=fn: fn(100_000, value), args.runs)
        print(f"  largest of 325 values, {name:<22s} {t / 100_000 * 1e9:6.1f} ns")


if __name__ == "__main__":
    main()
