"""The pad's contact response with E^-T solved column by column (LAPACK) or row by row.

``fretbem.bem.system.ROW_SOLVE_MIN`` decides which; one process, the pad of the reference
scene (BEM bodies) factorised once, the two settings alternating, CPU ms of
``contact_response`` (medians) and the largest difference of the traction maps relative
to their largest entry.

    OPENBLAS_NUM_THREADS=1 python benchmarks/face_response.py --pairs 241 481 --rounds 15
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from fretbem.bem import system
from fretbem.scenes import reference as scenes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[241, 481])
    parser.add_argument("--rounds", type=int, default=15)
    args = parser.parse_args()
    kept = system.ROW_SOLVE_MIN
    settings = {"columns": 10**9, "rows": kept}
    print(f"load {os.getloadavg()[0]:.2f}")
    try:
        for pairs in args.pairs:
            pair = scenes.cattaneo_mindlin(pairs=pairs, models={}).pair
            pad, tag = pair.upper, pair.upper_tag
            pad.system((tag,))
            times: dict[str, list[float]] = {name: [] for name in settings}
            maps = {}
            for _ in range(args.rounds):
                for name, least in settings.items():
                    system.ROW_SOLVE_MIN = least
                    start = time.process_time()
                    maps[name] = system.contact_response(pad, tag).traction_map
                    times[name].append(time.process_time() - start)
            scale = np.max(np.abs(maps["columns"]))
            moved = np.max(np.abs(maps["rows"] - maps["columns"])) / scale
            for name in settings:
                print(
                    f"{pairs} pairs, {name}: {statistics.median(times[name]) * 1e3:.1f} ms"
                    + (f", traction map moved {moved:.1e}" if name == "rows" else "")
                )
    finally:
        system.ROW_SOLVE_MIN = kept
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
