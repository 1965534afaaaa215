"""Compiled (numba) far-field loop of the stress evaluation matrix.

One pass over (point, element, quadrature point): the Kelvin stress kernels of
:mod:`fretbem.bem.stress_kernels` (same formulas, written per component) times the shape
functions, added straight into the matrices, and the moments of the linear field for the
points that use singularity subtraction. Importing this module imports numba; the numpy
path in :mod:`fretbem.bem.stresses` gives the same numbers without it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_JIT = {"cache": True, "nogil": True, "error_model": "numpy", "fastmath": True}


@numba.njit(**_JIT)
def _kernels(rx, ry, nx, ny, nu, mu, d, s):
    """Fill d[k, c] and s[k, c] (c = xx, yy, xy) for offset r = y - x and normal n at y:
    the formulas of :func:`fretbem.bem.stress_kernels.stress_kernels`, expanded by component."""
    inv_r = 1.0 / math.sqrt(rx * rx + ry * ry)
    gx = rx * inv_r
    gy = ry * inv_r
    dn = gx * nx + gy * ny
    a = 1.0 - 2.0 * nu
    b = 1.0 - 4.0 * nu
    cd = inv_r / (4.0 * math.pi * (1.0 - nu))
    cs = mu / (2.0 * math.pi * (1.0 - nu)) * inv_r * inv_r
    gxx = gx * gx
    gyy = gy * gy
    gxy = gx * gy
    d[0, 0] = cd * (a * gx + 2.0 * gx * gxx)
    d[0, 1] = cd * (-a * gx + 2.0 * gx * gyy)
    d[0, 2] = cd * (a * gy + 2.0 * gxx * gy)
    d[1, 0] = cd * (-a * gy + 2.0 * gxx * gy)
    d[1, 1] = cd * (a * gy + 2.0 * gy * gyy)
    d[1, 2] = cd * (a * gx + 2.0 * gx * gyy)
    dn2 = 2.0 * dn
    s[0, 0] = cs * (
        dn2 * (a * gx + 2.0 * nu * gx - 4.0 * gx * gxx)
        + 4.0 * nu * nx * gxx
        + a * (2.0 * nx * gxx + 2.0 * nx)
        - b * nx
    )
    s[0, 1] = cs * (
        dn2 * (a * gx - 4.0 * gx * gyy) + 4.0 * nu * ny * gxy + 2.0 * a * nx * gyy - b * nx
    )
    s[0, 2] = cs * (
        dn2 * (nu * gy - 4.0 * gxx * gy)
        + 2.0 * nu * (nx * gxy + ny * gxx)
        + a * (2.0 * nx * gxy + ny)
    )
    s[1, 0] = cs * (
        dn2 * (a * gy - 4.0 * gxx * gy) + 4.0 * nu * nx * gxy + 2.0 * a * ny * gxx - b * ny
    )
    s[1, 1] = cs * (
        dn2 * (a * gy + 2.0 * nu * gy - 4.0 * gy * gyy)
        + 4.0 * nu * ny * gyy
        + a * (2.0 * ny * gyy + 2.0 * ny)
        - b * ny
    )
    s[1, 2] = cs * (
        dn2 * (nu * gx - 4.0 * gx * gyy)
        + 2.0 * nu * (nx * gyy + ny * gxy)
        + a * (2.0 * ny * gxy + nx)
    )


@numba.njit(parallel=True, **_JIT)
def far_field(
    points, x, n, jw, phi, x4, n4, jw4, phi4, x2, n2, jw2, phi2, centre, coarse_radius,
    far_radius, cols, skip, sub_index,
    closest, nu, mu, full, mom_dn, mom_s, mom_sy,
):  # fmt: skip
    """Add the far pairs (skip[p, e] False) into full (m, 3, 2, N, 2): [p, c, 0, col, k] the
    D integrals, [p, c, 1, col, k] the S integrals; and the moments.

    Elements whose centre is farther than ``far_radius`` from a point use the 2-point rule
    (x2, ...), farther than ``coarse_radius`` the 4-point rule (x4, ...), the others the
    fine rule.
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
            c2 = cx * cx + cy * cy
            if c2 > far_radius[e] * far_radius[e]:
                xr, nr, wr, fr = x2, n2, jw2, phi2
            elif c2 > coarse_radius[e] * coarse_radius[e]:
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
                    for c in range(3):
                        for k in range(2):
                            full[p, c, 0, col, k] += d[k, c] * fw
                            full[p, c, 1, col, k] += s[k, c] * fw
                if si >= 0:
                    for k in range(2):
                        for c in range(3):
                            mom_s[si, k, c] += s[k, c] * w
                            for l_ in range(2):
                                mom_dn[si, k, c, l_] += d[k, c] * nr[e, q, l_] * w
                                mom_sy[si, k, c, l_] += (
                                    s[k, c] * (xr[e, q, l_] - closest[p, l_]) * w
                                )
