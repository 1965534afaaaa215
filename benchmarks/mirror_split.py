"""A symmetric body's system solved whole against as two mirror halves (issue 28, items 3 and 5).

The reference scene's pad (``cattaneo_mindlin(pairs=...)``, symmetric about the y axis) is
factorised and solved for all its parameter columns (:class:`fretbem.bem.system.BodySystem`,
H and G assembled once beforehand) in two ways, interleaved round by round in one process,
CPU seconds, one BLAS thread:

- ``full``: one LU of A (2/3 N^3 flops) and its solves (2 N^2 per column);
- ``halves``: :mod:`fretbem.bem.mirror_split`, the even and odd half systems (a quarter of
  both), their construction and symmetry check (``build``, also timed on its own) included,
  at every size (the run splits from ``mirror_split.MIN_ROWS`` rows, set from this).

``--keep`` lets a body of at most :data:`fretbem.bem.image_factor.KEEP_MAX_ROWS` rows keep
A for a point image (the run's path: both ways then also build A and copy it); by default
neither keeps, the path of a large body. Printed: medians, the ratio, each path's rate in
GFLOP/s of its own flops, and the largest difference of the unknowns (relative to the
largest unknown of each column group).

    OPENBLAS_NUM_THREADS=1 python benchmarks/mirror_split.py --pairs 481 961 --rounds 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np

from fretbem.bem import image_factor, mirror_split, system
from fretbem.bem.layout import CONTACT, TRACTION
from fretbem.numerics.blas import one_blas_thread
from fretbem.scenes import cattaneo_mindlin

MIRROR_SPLIT = system._mirror_split


def solve(body, tag, split: bool):
    """A fresh BodySystem of ``body`` (CPU seconds, the system), whole or split."""
    system._mirror_split = MIRROR_SPLIT if split else (lambda body, kinds: None)
    image_factor.clear()
    body._cache.pop(("system", (tag,)), None)
    start = time.process_time()
    out = system.BodySystem(body, (tag,))
    return time.process_time() - start, out


def build_seconds(body, tag) -> float:
    """CPU seconds of the halves' construction and symmetry check alone."""
    layout = body.layout((tag,))
    kinds = layout.kinds.ravel()
    split = MIRROR_SPLIT(body, kinds)
    h, g = body.system_matrices(system.g_free_segments(body, layout))
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    start = time.process_time()
    mirror_split.build(split, h, g, solves_u, np.flatnonzero(kinds == CONTACT))
    return time.process_time() - start


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[481, 961])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--keep", action="store_true", help="let small bodies keep A")
    args = parser.parse_args(argv)
    mirror_split.MIN_ROWS = 0  # the split at every size (the run's threshold is what it sets)
    if not args.keep:
        image_factor.KEEP_MAX_ROWS = 0
    bodies = {}
    for pairs in args.pairs:
        pair = cattaneo_mindlin(pairs=pairs).pair
        body, tag = pair.upper, pair.upper_tag
        body.system_matrices(system.g_free_segments(body, body.layout((tag,))))
        bodies[pairs] = body, tag
    load = [os.getloadavg()[0]]
    rows = {pairs: {"full": [], "halves": [], "build": []} for pairs in args.pairs}
    last = {}
    with one_blas_thread():
        for _ in range(args.rounds):
            for pairs, (body, tag) in bodies.items():
                for name, split in (("full", False), ("halves", True)):
                    seconds, out = solve(body, tag, split)
                    rows[pairs][name].append(seconds)
                    last[pairs, name] = out
                rows[pairs]["build"].append(build_seconds(body, tag))
    system._mirror_split = MIRROR_SPLIT
    load.append(os.getloadavg()[0])
    for pairs, times in rows.items():
        full, halves = last[pairs, "full"], last[pairs, "halves"]
        n, columns = len(full.kinds), 3 + full.contact_response.shape[1]
        flops = 2 / 3 * n**3 + 2 * n * n * columns
        median = {name: statistics.median(values) for name, values in times.items()}
        differences = {
            name: float(
                np.abs(getattr(full, name) - getattr(halves, name)).max()
                / max(np.abs(getattr(full, name)).max(), 1e-300)
            )
            for name in ("base", "contact_response")
        }
        print(json.dumps({
            "pairs": pairs, "N": n, "columns": columns,
            "full s": round(median["full"], 4), "halves s": round(median["halves"], 4),
            "build s": round(median["build"], 4),
            "full / halves": round(median["full"] / median["halves"], 2),
            "full GFLOP/s": round(flops / median["full"] / 1e9, 1),
            "halves GFLOP/s (their quarter)": round(flops / 4 / median["halves"] / 1e9, 1),
            "largest difference": differences,
        }))  # fmt: skip
    print(f"load average {load[0]:.1f} -> {load[1]:.1f}")


if __name__ == "__main__":
    main()
