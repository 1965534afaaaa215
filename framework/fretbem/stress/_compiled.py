"""Compiled (numba) far-field loop of the stress evaluation matrix.

One pass over (point, element, quadrature point): the Kelvin stress kernels of
:mod:`fretbem.stress.kernels` (same formulas, written per component) times the shape
functions, added straight into the matrices, and the moments of the linear field for the
points that use singularity subtraction. Importing this module imports numba; the numpy
path in :mod:`fretbem.stress.somigliana` gives the same numbers without it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}


@numba.njit(**_JIT)
def _delta(i, j):
    return 1.0 if i == j else 0.0


@numba.njit(**_JIT)
def _kernels(rx, ry, nx, ny, nu, mu, d, s):
    """Fill d[k, c] and s[k, c] (c = xx, yy, xy) for offset r = y - x and normal n at y."""
    r2 = rx * rx + ry * ry
    inv_r = 1.0 / math.sqrt(r2)
    g0 = rx * inv_r
    g1 = ry * inv_r
    dn = g0 * nx + g1 * ny
    a = 1.0 - 2.0 * nu
    d_scale = inv_r / (4.0 * math.pi * (1.0 - nu))
    s_scale = mu / (2.0 * math.pi * (1.0 - nu)) * inv_r * inv_r
    for k in range(2):
        gk = g0 if k == 0 else g1
        nk = nx if k == 0 else ny
        for c in range(3):
            i = 0 if c == 0 else 1
            j = 0 if c != 1 else 1
            if c == 2:
                i, j = 0, 1
            gi = g0 if i == 0 else g1
            gj = g0 if j == 0 else g1
            ni = nx if i == 0 else ny
            nj = nx if j == 0 else ny
            d[k, c] = d_scale * (
                a * (_delta(k, i) * gj + _delta(k, j) * gi - _delta(i, j) * gk) + 2.0 * gi * gj * gk
            )
            s[k, c] = s_scale * (
                2.0
                * dn
                * (
                    a * _delta(i, j) * gk
                    + nu * (_delta(i, k) * gj + _delta(j, k) * gi)
                    - 4.0 * gi * gj * gk
                )
                + 2.0 * nu * (ni * gj * gk + nj * gi * gk)
                + a * (2.0 * nk * gi * gj + nj * _delta(i, k) + ni * _delta(j, k))
                - (1.0 - 4.0 * nu) * nk * _delta(i, j)
            )


@numba.njit(parallel=True, **_JIT)
def far_field(
    points, x, n, jw, phi, x4, n4, jw4, phi4, centre, coarse_radius, cols, skip, sub_index,
    closest, nu, mu, mt, mu_, mom_dn, mom_s, mom_sy,
):  # fmt: skip
    """Add the far pairs (skip[p, e] False) into mt, mu_ (m, N, 2, 3) and the moments.

    Elements whose centre is farther than ``coarse_radius`` from a point use the coarse
    rule (x4, n4, jw4, phi4); the others the fine rule.
    """
    m = points.shape[0]
    n_el = phi.shape[0]
    n_loc = phi.shape[2]
    for p in numba.prange(m):
        d = np.empty((2, 3))
        s = np.empty((2, 3))
        px = points[p, 0]
        py = points[p, 1]
        si = sub_index[p]
        for e in range(n_el):
            if skip[p, e]:
                continue
            cx = centre[e, 0] - px
            cy = centre[e, 1] - py
            if cx * cx + cy * cy > coarse_radius[e] * coarse_radius[e]:
                xr, nr, wr, fr = x4, n4, jw4, phi4
            else:
                xr, nr, wr, fr = x, n, jw, phi
            for q in range(wr.shape[1]):
                w = wr[e, q]
                _kernels(xr[e, q, 0] - px, xr[e, q, 1] - py, nr[e, q, 0], nr[e, q, 1], nu, mu, d, s)
                for a in range(n_loc):
                    fw = fr[e, q, a] * w
                    if fw == 0.0:
                        continue
                    col = cols[e, a]
                    for k in range(2):
                        for c in range(3):
                            mt[p, col, k, c] += d[k, c] * fw
                            mu_[p, col, k, c] += s[k, c] * fw
                if si >= 0:
                    for k in range(2):
                        for c in range(3):
                            mom_s[si, k, c] += s[k, c] * w
                            for l_ in range(2):
                                mom_dn[si, k, c, l_] += d[k, c] * nr[e, q, l_] * w
                                mom_sy[si, k, c, l_] += (
                                    s[k, c] * (xr[e, q, l_] - closest[p, l_]) * w
                                )
