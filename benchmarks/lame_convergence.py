"""Lamé thick cylinder: h-convergence and timings of every built-in basis family.

A quarter annulus (a = 1, b = 2) under internal pressure p = 10 (E = 1000, nu = 0.3, plane
strain), on rollers along both straight edges. For each family and refinement the script
prints the radial displacement error on the outer arc, the hoop traction error on the left
edge (max and L2), assembly and solve times, the fitted convergence rates, and the median
assembly time of a body of about 1000 unknowns.

Run from the repository root::

    python benchmarks/lame_convergence.py --levels 2 4 8 16 32 64 --out lame.csv
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from fretbem.basis import Refinement
from fretbem.bem.body import BemBody
from fretbem.conditions import Displacement, Traction
from fretbem.geometry.boundary import Boundary, Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material

A, B, P = 1.0, 2.0, 10.0
E, NU = 1000.0, 0.3
FAMILIES = ("nurbs", "lagrange2")
TAGS = ("bottom", "outer", "left", "inner")
BOUNDARY = Boundary(
    [
        Segment("bottom", NurbsCurve.line([A, 0], [B, 0])),
        Segment("outer", NurbsCurve.arc([0, 0], B, 0, math.pi / 2)),
        Segment("left", NurbsCurve.line([0, B], [0, A])),
        Segment("inner", NurbsCurve.arc([0, 0], A, math.pi / 2, 0)),
    ]
)
COLUMNS = (
    "family",
    "elements",
    "dofs",
    "displacement_error",
    "hoop_error_max",
    "hoop_error_l2",
    "assembly_s",
    "solve_s",
)


def radial_displacement(r):
    """Exact u_r(r)."""
    return (1 + NU) / E * A**2 * P / (B**2 - A**2) * ((1 - 2 * NU) * r + B**2 / r)


def hoop_stress(r):
    """Exact sigma_theta(r)."""
    return A**2 * P / (B**2 - A**2) * (1 + B**2 / r**2)


def make_body(family: str, elements: int) -> BemBody:
    """The Lamé body with ``elements`` uniform elements on every segment."""
    pressure = [lambda x, c=c: P * x[:, c] / np.linalg.norm(x, axis=1) for c in range(2)]
    return BemBody(
        BOUNDARY,
        Material(E, NU),
        [
            Displacement("bottom", x=None, y=0.0),
            Displacement("left", x=0.0, y=None),
            Traction("inner", x=pressure[0], y=pressure[1]),
        ],
        basis=family,
        refinement={tag: Refinement(elements) for tag in TAGS},
    )


def run(family: str, elements: int) -> dict[str, float | int | str]:
    """Solve once; errors are relative to the peak exact values."""
    body = make_body(family, elements)
    start = time.perf_counter()
    body.matrices()
    assembly = time.perf_counter() - start
    start = time.perf_counter()
    solution = body.solve()
    solve = time.perf_counter() - start

    s = np.linspace(0.0, 1.0, 401)
    outer = solution.points(1, s)
    radius = np.linalg.norm(outer, axis=1)
    u_r = np.sum(solution.displacement(1, s) * outer / radius[:, None], axis=1)
    u_error = np.abs(u_r - radial_displacement(B)).max() / radial_displacement(B)

    left = body.segments[2]
    hoop_max = np.abs(-solution.traction(2, s)[:, 0] - hoop_stress(solution.points(2, s)[:, 1]))
    # L2 over the edge: 8-point Gauss on every element of the left segment
    x, w = np.polynomial.legendre.leggauss(8)
    elements_q = np.repeat(np.arange(left.n_elements), x.size)
    local = np.tile(x, left.n_elements)
    points, _, jacobians, _ = left.geometry(elements_q, local)
    params = left.to_parameter(elements_q, local)
    weights = jacobians * np.tile(w, left.n_elements)
    exact = hoop_stress(points[:, 1])
    error = -solution.traction(2, params)[:, 0] - exact
    hoop_l2 = math.sqrt(np.sum(weights * error**2) / np.sum(weights * exact**2))
    return {
        "family": family,
        "elements": elements,
        "dofs": body.dofs,
        "displacement_error": float(u_error),
        "hoop_error_max": float(hoop_max.max() / hoop_stress(A)),
        "hoop_error_l2": hoop_l2,
        "assembly_s": assembly,
        "solve_s": solve,
    }


def rate(elements, errors) -> float:
    """Least-squares slope of log(error) against log(h), h = 1 / elements."""
    return float(np.polyfit(-np.log(elements), np.log(errors), 1)[0])


def elements_for_dofs(family: str, target: int) -> int:
    """Elements per segment giving the body closest to ``target`` unknowns."""
    best, best_gap, elements = 1, math.inf, 1
    while True:
        gap = make_body(family, elements).dofs - target
        if abs(gap) < best_gap:
            best, best_gap = elements, abs(gap)
        if gap > 0:
            return best
        elements += 1


def assembly_time(family: str, elements: int, repeats: int = 5) -> tuple[int, float]:
    """(dofs, median seconds of body.matrices()) over fresh bodies (matrices are cached)."""
    times = []
    for _ in range(repeats):
        body = make_body(family, elements)
        body.segments  # discretise outside the timed region  # noqa: B018
        start = time.perf_counter()
        body.matrices()
        times.append(time.perf_counter() - start)
    return body.dofs, statistics.median(times)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--levels", type=int, nargs="+", default=[2, 4, 8, 16, 32, 64],
        help="elements per segment (default: 2 4 8 16 32 64)",
    )  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("lame_convergence.csv"), help="CSV path")
    parser.add_argument(
        "--dofs", type=int, default=1000, help="size of the assembly-timing body (default 1000)"
    )
    args = parser.parse_args(argv)

    print(f"platform: {platform.platform()}, Python {platform.python_version()}")
    print(f"cores (os.cpu_count()): {os.cpu_count()}")
    print()
    header = (
        f"{'family':<10} {'elements':>8} {'dofs':>6} {'u error':>10} {'hoop max':>10} "
        f"{'hoop L2':>10} {'assembly s':>10} {'solve s':>8}"
    )
    print(header)
    print("-" * len(header))
    rows = []
    for family in FAMILIES:
        for elements in args.levels:
            row = run(family, elements)
            rows.append(row)
            print(
                f"{family:<10} {elements:>8} {row['dofs']:>6} {row['displacement_error']:>10.3e} "
                f"{row['hoop_error_max']:>10.3e} {row['hoop_error_l2']:>10.3e} "
                f"{row['assembly_s']:>10.3f} {row['solve_s']:>8.3f}"
            )
    print()
    if len(args.levels) > 1:
        print("fitted rates (slope of log error vs log h, all levels):")
        for family in FAMILIES:
            mine = [r for r in rows if r["family"] == family]
            levels = [r["elements"] for r in mine]
            rates = {key: rate(levels, [r[key] for r in mine]) for key in COLUMNS[3:6]}
            print(
                f"  {family:<10} displacement {rates['displacement_error']:.2f}   "
                f"hoop max {rates['hoop_error_max']:.2f}   hoop L2 {rates['hoop_error_l2']:.2f}"
            )
        print()
    print(f"assembly of a body of about {args.dofs} unknowns (median of 5, fresh Body each):")
    for family in FAMILIES:
        elements = elements_for_dofs(family, args.dofs)
        dofs, seconds = assembly_time(family, elements)
        print(f"  {family:<10} {elements:>4} elements/segment  {dofs:>5} dofs  {seconds:.3f} s")

    with args.out.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
