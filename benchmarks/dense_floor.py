"""The dense solve of one body, float64 against mixed precision (issue 28, large problems).

A body's collocation system is solved for all its parameter columns at once: A^-1 P with P
(N x ~N) holding the contact face's G columns, since the face holds ~98 % of the unknowns.
That is an LU (2/3 N^3 flops) and two triangular solves with ~N right-hand sides (2 N^3).
Mixed precision (LAPACK's dsgesv: an LU in float32 and float64 iterative refinement) pays
where the right-hand sides are few; here every refinement sweep needs the float64
residual P - A X, a product of 2 N^3 flops, as much as the float64 solves it would replace.

This script measures it on the reference scene's pad (``cattaneo_mindlin(pairs=...)``), CPU
seconds, one BLAS thread, medians of ``--rounds`` interleaved rounds:

- ``float64``: dgetrf + dgetrs (what :class:`fretbem.bem.system.BodySystem` does);
- ``float32 LU + solve``: sgetrf + sgetrs, and its error against float64;
- ``refinement sweep``: the float64 residual (dgemm) and the float32 correction (sgetrs);
  the sweeps needed to bring the largest difference to the float64 answer below
  ``--target`` (relative to its largest entry), and the total mixed-precision time;
- ``dgemm N x N x N``: the peak the solve is compared with (GFLOP/s printed).

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/dense_floor.py --pairs 481 961 --rounds 3
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np
import scipy.linalg as sla

from fretbem.bem.layout import BLOCK, CONTACT, TRACTION
from fretbem.bem.system import collocation_system
from fretbem.numerics.blas import one_blas_thread
from fretbem.scenes import cattaneo_mindlin


def system_of(pairs: int) -> tuple[np.ndarray, np.ndarray]:
    """A and P of the reference scene's pad at ``pairs`` (F-ordered, float64)."""
    pair = cattaneo_mindlin(pairs=pairs).pair
    body, tag = pair.upper, pair.upper_tag
    h, g = body.matrices()
    system_layout = body.layout((tag,))
    kinds, known = system_layout.kinds.ravel(), system_layout.known.ravel()
    loads = system_layout.loads.reshape(len(system_layout.loads), kinds.size)
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    return collocation_system(
        h, g, kinds, known, loads, solves_u, np.flatnonzero(kinds == BLOCK),
        np.flatnonzero(kinds == CONTACT),
    )  # fmt: skip


def timed(fn):
    start = time.process_time()
    out = fn()
    return time.process_time() - start, out


def float64_solve(a, p):
    lu, piv, _ = sla.lapack.dgetrf(a)
    return sla.lapack.dgetrs(lu, piv, p)[0]


def mixed(a, p, reference, target, sweeps):
    """float32 LU and solve, then float64 refinement sweeps; times and errors per stage."""
    seconds, (lu, piv) = timed(lambda: sla.lapack.sgetrf(a.astype(np.float32, order="F"))[:2])
    solve_s, x = timed(lambda: sla.lapack.sgetrs(lu, piv, p.astype(np.float32, order="F"))[0])
    x = x.astype(np.float64)
    scale = np.max(np.abs(reference))
    errors = [float(np.max(np.abs(x - reference)) / scale)]
    sweep_times = []
    for _ in range(sweeps):
        if errors[-1] <= target:
            break
        residual_s, residual = timed(lambda: p - a @ x)  # noqa: B023
        correct_s, d = timed(
            lambda: sla.lapack.sgetrs(lu, piv, residual.astype(np.float32, order="F"))[0]  # noqa: B023
        )
        x += d
        sweep_times.append((residual_s, correct_s))
        errors.append(float(np.max(np.abs(x - reference)) / scale))
    return {"sgetrf": seconds, "sgetrs": solve_s, "sweeps": sweep_times, "errors": errors}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[481, 961])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--target", type=float, default=1e-12)
    parser.add_argument("--sweeps", type=int, default=6)
    args = parser.parse_args(argv)
    systems = {pairs: system_of(pairs) for pairs in args.pairs}
    rows: dict[int, list] = {pairs: [] for pairs in args.pairs}
    load = [os.getloadavg()[0]]
    with one_blas_thread():
        for _ in range(args.rounds):
            for pairs, (a, p) in systems.items():
                f64, reference = timed(lambda a=a, p=p: float64_solve(a, p))
                gemm, _ = timed(lambda a=a: a @ a)
                run = mixed(a, p, reference, args.target, args.sweeps)
                rows[pairs].append((f64, gemm, run))
    load.append(os.getloadavg()[0])
    for pairs, runs in rows.items():
        n, cols = systems[pairs][1].shape
        f64 = statistics.median(r[0] for r in runs)
        gemm = statistics.median(r[1] for r in runs)
        last = runs[-1][2]
        s_lu = statistics.median(r[2]["sgetrf"] for r in runs)
        s_solve = statistics.median(r[2]["sgetrs"] for r in runs)
        sweeps = [sum(t) for t in last["sweeps"]]
        total = s_lu + s_solve + sum(sweeps)
        met = last["errors"][-1] <= args.target
        print(json.dumps({
            "pairs": pairs, "N": n, "columns": cols,
            "float64 LU + solve s": round(f64, 3),
            "float64 GFLOP/s": round((2 / 3 * n**3 + 2 * n * n * cols) / f64 / 1e9, 1),
            "dgemm NxNxN GFLOP/s": round(2 * n**3 / gemm / 1e9, 1),
            "float32 LU s": round(s_lu, 3), "float32 solve s": round(s_solve, 3),
            "float32 error": last["errors"][0],
            "sweep s (residual, correction)": [[round(x, 3) for x in t] for t in last["sweeps"]],
            "errors after sweeps": last["errors"][1:],
            "mixed total s": round(total, 3), "target met": met,
            "mixed / float64": round(total / f64, 2),
        }))  # fmt: skip
    print(f"load average {load[0]:.1f} -> {load[1]:.1f}")


if __name__ == "__main__":
    main()
