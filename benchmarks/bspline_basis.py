"""B-spline basis evaluation: fretbem's vectorised Cox-de Boor against scipy's design matrix.

The element-local form fretbem needs ((m, p + 1) blocks and derivatives) is built from
``scipy.interpolate.BSpline.design_matrix`` (values; derivatives from the degree p - 1
matrix) and compared with ``fretbem.geometry.nurbs.bspline_basis``. Median of 7 runs.

    python benchmarks/bspline_basis.py
"""

from __future__ import annotations

import os
import platform
import statistics
import timeit

import numpy as np
from scipy.interpolate import BSpline

from fretbem.geometry import knots as kv
from fretbem.geometry.nurbs import bspline_basis


def scipy_local(knots, degree, xi):
    """Element-local values and derivatives through scipy's sparse design matrices."""
    n = knots.size - degree - 1
    first = np.clip(np.searchsorted(knots, xi, side="right") - 1, degree, n - 1) - degree

    def local(matrix, start, width):
        coo = matrix.tocoo()
        j = coo.col - start[coo.row]
        keep = (j >= 0) & (j < width)
        out = np.zeros((matrix.shape[0], width))
        out[coo.row[keep], j[keep]] = coo.data[keep]
        return out

    values = local(BSpline.design_matrix(xi, knots, degree), first, degree + 1)
    lower = local(BSpline.design_matrix(xi, knots[1:-1], degree - 1), first - 1, degree + 2)
    j = first[:, None] + np.arange(degree + 2)
    gap = knots[np.minimum(j + degree, knots.size - 1)] - knots[np.minimum(j, knots.size - 1)]
    scaled = lower * np.divide(degree, gap, out=np.zeros_like(gap), where=gap > 0)
    return values, scaled[:, :-1] - scaled[:, 1:], first


def main() -> None:
    print(
        f"{os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
        f"python {platform.python_version()}"
    )
    print("degree  points  scipy ms  fretbem ms  ratio  max diff")
    rng = np.random.default_rng(0)
    for degree in (2, 3, 4):
        knots = kv.open_uniform(degree, 50)
        for m in (100, 10_000):
            xi = rng.random(m)
            ref, ours = scipy_local(knots, degree, xi), bspline_basis(knots, degree, xi)
            diff = max(np.abs(a - b).max() for a, b in zip(ref[:2], ours[:2], strict=True))
            times = []
            for fn in (scipy_local, bspline_basis):
                runs = timeit.repeat(
                    lambda fn=fn, k=knots, p=degree, x=xi: fn(k, p, x), number=10, repeat=7
                )
                times.append(statistics.median(runs) / 10 * 1e3)
            print(
                f"{degree:6d} {m:7d} {times[0]:9.3f} {times[1]:11.3f} {times[0] / times[1]:6.1f}"
                f"  {diff:.1e}"
            )


if __name__ == "__main__":
    main()
