"""Knot insertion's refinement operator (the Oslo algorithm) against the Greville collocation
solve it replaced, in one process, alternating.

A curve refined as the reference scene refines its faces (a rational quadratic arc, a
degree-1 line elevated first goes the collocation way either way) and cubics, at 61, 481
and 2,001 control points: ``NurbsCurve.refine`` with the operator cache emptied before each
call, once through the insertion operator and once through the collocation solve and its
check (the insertion path switched off). Microseconds, medians of ``--rounds``; the largest
difference of the two operators is printed too (round-off: tests/framework/geometry).

    OPENBLAS_NUM_THREADS=1 python benchmarks/nurbs_knot_insertion.py --rounds 30
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np

from fretbem.geometry import knots as kv
from fretbem.geometry import nurbs

INSERTION = nurbs._contains


def _collocation(new_knots, knots) -> bool:  # the insertion path switched off
    return False


def refine_us(curve, knots, contains) -> tuple[float, np.ndarray]:
    nurbs._contains = contains
    try:
        nurbs._OPERATORS.clear()
        start = time.perf_counter()
        _, transform = curve.refine(knots)
        return (time.perf_counter() - start) * 1e6, transform
    finally:
        nurbs._contains = INSERTION


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30)
    args = parser.parse_args()
    arc = nurbs.NurbsCurve.arc((0.0, 70.0), 70.0, -math.pi / 2 - 0.05, -math.pi / 2 + 0.05)
    rng = np.random.default_rng(0)
    interior = np.sort(rng.uniform(0.1, 0.9, 3))
    cubic_knots = np.concatenate([np.zeros(4), interior, np.ones(4)])
    cubic = nurbs.NurbsCurve(3, cubic_knots, rng.normal(size=(7, 2)), rng.uniform(0.5, 2, 7))
    print(f"load {os.getloadavg()[0]:.2f}; us per refine, medians of {args.rounds}")
    for name, curve in (("arc, degree 2", arc), ("cubic, degree 3", cubic)):
        for points in (61, 481, 2001):
            added = np.linspace(0.0, 1.0, points - curve.n_control_points + 2)[1:-1]
            knots = kv.insert(curve.knots, added)
            times = {"insertion": [], "collocation": []}
            for _ in range(args.rounds):
                t_new, new = refine_us(curve, knots, INSERTION)
                t_old, old = refine_us(curve, knots, _collocation)
                times["insertion"].append(t_new)
                times["collocation"].append(t_old)
            new_us = statistics.median(times["insertion"])
            old_us = statistics.median(times["collocation"])
            print(f"{name:16s} {knots.size - curve.degree - 1:5d} points: collocation "
                  f"{old_us:8.1f}, insertion {new_us:8.1f} ({old_us / new_us:5.1f}x); "
                  f"max |T_new - T_old| {np.abs(new - old).max():.1e}")  # fmt: skip


if __name__ == "__main__":
    main()
