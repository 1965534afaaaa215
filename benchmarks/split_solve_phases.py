"""One large mirror-symmetric body's split solve, this tree's code against another's (issue 28).

The reference scene's pad at ``--pairs`` is assembled once; its H and G then go through
:func:`fretbem.bem.mirror_split.build`, :class:`~fretbem.bem.mirror_split.SplitFactor` and
``solve_contact`` (the contact columns A^-1 G[:, C], the largest part of the condensation)
with this tree's ``mirror_split`` module and with the one of ``--before`` (a checkout; its
module is loaded from the file under another name), the two alternating round by round in
one process. CPU seconds per phase, medians, and whether the contact columns are equal bit
for bit. The LAPACK floor of the phase is printed beside it: 2/3 n^3 per half LU and
2 n^2 m per half's m right-hand sides, at this machine's dgemm rate (measured here).

    OPENBLAS_NUM_THREADS=1 python benchmarks/split_solve_phases.py --before /tmp/m9d \\
        --pairs 1921 --rounds 3
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np
from tree_module import tree_module

from fretbem.bem import mirror, mirror_split
from fretbem.bem.layout import CONTACT, TRACTION
from fretbem.numerics.blas import one_blas_thread
from fretbem.scenes import cattaneo_mindlin


def module_of(tree: str):
    """``fretbem.bem.mirror_split`` of another checkout, loaded under another name."""
    return tree_module(tree, "fretbem.bem.mirror_split", "before_mirror_split")


def gemm_rate(n: int = 2000) -> float:
    """dgemm flop/s on one thread (n x n x n), best of three."""
    a, b = np.random.default_rng(0).normal(size=(2, n, n))
    best = np.inf
    for _ in range(3):
        start = time.process_time()
        a @ b
        best = min(best, time.process_time() - start)
    return 2 * n**3 / best


def one_round(module, body, kinds, solves_u, contact, h, g) -> tuple[dict, np.ndarray]:
    """CPU s of build, factorisation and contact solve with ``module``; the contact columns."""
    split = module.MirrorSplit.of(*_split_args(body))
    seconds = {}
    start = time.process_time()
    halves = module.build(split, h, g, solves_u, contact)
    seconds["build"] = time.process_time() - start
    start = time.process_time()
    factor = module.SplitFactor(split, halves)
    seconds["factorisation"] = time.process_time() - start
    del halves
    out = np.empty((len(kinds), len(contact)), order="F")
    start = time.process_time()
    factor.solve_contact(contact, out)
    seconds["contact solve"] = time.process_time() - start
    return seconds, out


def _split_args(body):
    """The functions' mirror and representatives (:meth:`MirrorSplit.of`'s arguments)."""
    colloc = body.collocation
    q = mirror.permutation(body.segments, None, colloc.points, body.offsets)
    return q, mirror.integrated_rows(q, colloc.points)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="the other checkout's root")
    parser.add_argument("--pairs", type=int, default=1921)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    before = module_of(args.before)
    pair = cattaneo_mindlin(pairs=args.pairs, models={}).pair
    body, tag = pair.upper, pair.upper_tag
    layout = body.layout((tag,))
    kinds = layout.kinds.ravel()
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    contact = np.flatnonzero(kinds == CONTACT)
    h, g = body.matrices()
    n_half = len(kinds) / 2
    rate = gemm_rate()
    floors = {
        "factorisation": 2 * (2 / 3) * n_half**3 / rate,
        "contact solve": 2 * 2 * n_half**2 * (len(contact) / 2) / rate,
    }
    print(f"load {os.getloadavg()[0]:.2f}; {len(kinds)} rows, {len(contact)} contact columns; "
          f"dgemm {rate / 1e9:.1f} GFLOP/s")  # fmt: skip
    times = {"before": [], "this tree": []}
    columns = {}
    with one_blas_thread():
        for _ in range(args.rounds):
            for name, module in (("before", before), ("this tree", mirror_split)):
                seconds, out = one_round(module, body, kinds, solves_u, contact, h, g)
                times[name].append(seconds)
                columns[name] = out
                del out
    for name, rounds in times.items():
        medians = {key: statistics.median(r[key] for r in rounds) for key in rounds[0]}
        shown = ", ".join(
            f"{key} {value:.2f} s" + (f" (floor {floors[key]:.2f})" if key in floors else "")
            for key, value in medians.items()
        )
        print(f"{name}: {shown}")
    same = np.array_equal(columns["before"], columns["this tree"])
    print(f"contact columns bit-identical: {same}; load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
