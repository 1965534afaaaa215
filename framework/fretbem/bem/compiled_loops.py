"""Compiled (numba) loops of the collocation assembly: classify, integrate, scatter.

The numpy assembler evaluates the far field on dense (rows, elements, points) blocks and
scatters through temporaries; here one loop per (collocation point, element) pair decides
the pair's class, integrates far and mid pairs straight into H and G with the same rules
and the same kernel formulas as :func:`fretbem.bem.kernels.traction_and_displacement`, and
hands near and singular pairs back to the numpy code (few, and they need the basis).

Classification is the numpy assembler's, exactly: the distance of a point to an element
is the minimum over 9 samples; a bounding circle of the samples decides most pairs
without touching the samples (the circle's distance is a lower bound of the minimum).

Functions are compiled on first use and cached on disk (``cache=True``), so a fresh
process pays only numba's import and the cache load. Importing this module imports numba:
:mod:`fretbem.bem.integration` imports it lazily, only for problems large enough to repay it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: pair classes written by :func:`classify_and_integrate`
FAR, MID, NEAR, SINGULAR = 0, 1, 2, 3


@numba.njit(**_JIT)
def _integrate_pair(s, row, e, x, n, jw, phi, cols, t_scale, u_scale, a, log_coef, h, g, acc):
    """Add one element's integral against one collocation point to H and G (rows 2 s + i).

    ``acc`` is a (7, n_local) scratch of the caller's (zeroed here): no allocation per pair.
    """
    n_q, n_loc = phi.shape[1], phi.shape[2]
    sx, sy = row[0], row[1]
    acc[:, :n_loc] = 0.0
    h00, h01, h10, h11, g00, g01, g11 = acc[0], acc[1], acc[2], acc[3], acc[4], acc[5], acc[6]
    for q in range(n_q):
        rx = x[e, q, 0] - sx
        ry = x[e, q, 1] - sy
        d2 = rx * rx + ry * ry
        inv = 1.0 / d2
        ux = rx * rx * inv
        uy = ry * ry * inv
        uxy = rx * ry * inv
        nx = n[e, q, 0]
        ny = n[e, q, 1]
        dr_dn = (rx * nx + ry * ny) * inv
        skew = a * (rx * ny - ry * nx) * inv
        w = jw[e, q]
        tw = t_scale * w
        t00 = tw * dr_dn * (a + 2.0 * ux)
        t11 = tw * dr_dn * (a + 2.0 * uy)
        t01 = tw * (dr_dn * 2.0 * uxy - skew)
        t10 = tw * (dr_dn * 2.0 * uxy + skew)
        uw = u_scale * w
        log_term = log_coef * 0.5 * math.log(d2)
        u00 = uw * (log_term + ux)
        u11 = uw * (log_term + uy)
        u01 = uw * uxy
        for k in range(n_loc):
            f = phi[e, q, k]
            h00[k] += t00 * f
            h01[k] += t01 * f
            h10[k] += t10 * f
            h11[k] += t11 * f
            g00[k] += u00 * f
            g01[k] += u01 * f
            g11[k] += u11 * f
    r0, r1 = 2 * s, 2 * s + 1
    for k in range(n_loc):
        c0 = 2 * cols[e, k]
        c1 = c0 + 1
        h[r0, c0] += h00[k]
        h[r0, c1] += h01[k]
        h[r1, c0] += h10[k]
        h[r1, c1] += h11[k]
        g[r0, c0] += g00[k]
        g[r0, c1] += g01[k]
        g[r1, c0] += g01[k]
        g[r1, c1] += g11[k]


@numba.njit(**_JIT)
def classify_and_integrate(
    rows,
    points,
    own,
    parameters,
    bounds,
    samples,
    centres,
    radii,
    length,
    far_x,
    far_n,
    far_jw,
    far_phi,
    mid_x,
    mid_n,
    mid_jw,
    mid_phi,
    cols,
    far_ratio,
    near_ratio,
    shear_modulus,
    nu,
    h,
    g,
):
    """Classify every (row, element) pair of one segment; integrate far and mid pairs.

    Returns the pairs left for the numpy code: (row index into ``rows``, element, class)
    for the near and singular pairs, in row-major order like ``np.nonzero``.
    """
    n_rows, n_el = rows.shape[0], bounds.shape[0]
    n_s = samples.shape[1]
    a = 1.0 - 2.0 * nu
    t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
    u_scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_coef = -(3.0 - 4.0 * nu)
    acc = np.empty((7, far_phi.shape[2]))
    left_p = np.empty(n_rows * 8 + 64, dtype=np.int64)
    left_e = np.empty_like(left_p)
    left_c = np.empty_like(left_p)
    n_left = 0
    for i in range(n_rows):
        s = rows[i]
        row = points[s]
        for e in range(n_el):
            if (
                own[s]
                and parameters[s] >= bounds[e, 0] - 1e-12
                and parameters[s] <= bounds[e, 1] + 1e-12
            ):
                kind = SINGULAR
            else:
                cx = row[0] - centres[e, 0]
                cy = row[1] - centres[e, 1]
                lower = math.sqrt(cx * cx + cy * cy) - radii[e]
                if lower * (1.0 - 1e-12) >= far_ratio * length[e]:
                    kind = FAR
                else:
                    best = np.inf
                    for k in range(n_s):
                        dx = row[0] - samples[e, k, 0]
                        dy = row[1] - samples[e, k, 1]
                        d = math.sqrt(dx * dx + dy * dy)
                        if d < best:
                            best = d
                    ratio = best / length[e]
                    if ratio >= far_ratio:
                        kind = FAR
                    elif ratio >= near_ratio:
                        kind = MID
                    else:
                        kind = NEAR
            if kind == FAR:
                _integrate_pair(
                    s, row, e, far_x, far_n, far_jw, far_phi, cols, t_scale, u_scale, a,
                    log_coef, h, g, acc,
                )  # fmt: skip
            elif kind == MID:
                _integrate_pair(
                    s, row, e, mid_x, mid_n, mid_jw, mid_phi, cols, t_scale, u_scale, a,
                    log_coef, h, g, acc,
                )  # fmt: skip
            else:
                if n_left == left_p.shape[0]:
                    grown = np.empty(2 * n_left, dtype=np.int64)
                    grown[:n_left] = left_p
                    left_p = grown
                    grown = np.empty(2 * n_left, dtype=np.int64)
                    grown[:n_left] = left_e
                    left_e = grown
                    grown = np.empty(2 * n_left, dtype=np.int64)
                    grown[:n_left] = left_c
                    left_c = grown
                left_p[n_left] = i
                left_e[n_left] = e
                left_c[n_left] = kind
                n_left += 1
    return left_p[:n_left], left_e[:n_left], left_c[:n_left]


@numba.njit(**_JIT)
def scatter_blocks(rows, cols, blocks, matrix):
    """matrix[2 rows[p] + i, 2 cols[p, a] + j] += blocks[p, i, a, j], no temporaries."""
    n_p, n_loc = cols.shape
    for p in range(n_p):
        r = 2 * rows[p]
        for i in range(2):
            for k in range(n_loc):
                c = 2 * cols[p, k]
                matrix[r + i, c] += blocks[p, i, k, 0]
                matrix[r + i, c + 1] += blocks[p, i, k, 1]


@numba.njit(**_JIT)
def dense_far_field(points, x, n, jw, phi, cols, shear_modulus, nu, h, g):
    """Every (point, element) pair with one rule into H and G: the compiled floor.

    No classification, no near or singular treatment: the least work any assembler of the
    same rule must do (``benchmarks/floor.py`` times it against the real assembly).
    """
    a = 1.0 - 2.0 * nu
    t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
    u_scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_coef = -(3.0 - 4.0 * nu)
    acc = np.empty((7, phi.shape[2]))
    for s in range(points.shape[0]):
        row = points[s]
        for e in range(x.shape[0]):
            _integrate_pair(
                s, row, e, x, n, jw, phi, cols, t_scale, u_scale, a, log_coef, h, g, acc
            )


@numba.njit(**_JIT)
def integrate_pairs(rows, points, x, n, jw, phi, cols, shear_modulus, nu, h, g):
    """Per-pair rules (pair p: points x[p], weights jw[p]) into H and G rows 2 rows[p] + i."""
    a = 1.0 - 2.0 * nu
    t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
    u_scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_coef = -(3.0 - 4.0 * nu)
    acc = np.empty((7, phi.shape[2]))
    for p in range(rows.shape[0]):
        s = rows[p]
        _integrate_pair(
            s, points[s], p, x, n, jw, phi, cols, t_scale, u_scale, a, log_coef, h, g, acc
        )


@numba.njit(**_JIT)
def integrate_singular(
    rows, points, x, n, jw, phi, at_source, t, safe, log_jw, log_phi, cols, shear_modulus, nu,
    h, g,
):  # fmt: skip
    """Elements split at their collocation point, pair by pair (both sides' pairs may come
    in one call; see ``fretbem.bem.assembly._singular_sides``).

    H: traction kernel against phi - phi(source), bounded after the subtraction. G: the
    smooth part r_i r_j / r^2 and ln(1/r) = -ln t - ln(r / t), the -ln t part by the
    log-weighted rule (``log_jw``, ``log_phi``) and the rest by Gauss.
    """
    a = 1.0 - 2.0 * nu
    t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
    scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_coef = scale * (3.0 - 4.0 * nu)
    n_q, n_loc = phi.shape[1], phi.shape[2]
    for p in range(rows.shape[0]):
        s = rows[p]
        sx, sy = points[s, 0], points[s, 1]
        hb = np.zeros((4, n_loc))
        gb = np.zeros((3, n_loc))
        log_safe = math.log(safe[p])
        for q in range(n_q):
            rx = x[p, q, 0] - sx
            ry = x[p, q, 1] - sy
            dist = math.sqrt(rx * rx + ry * ry)
            ex, ey = rx / dist, ry / dist
            nx, ny = n[p, q, 0], n[p, q, 1]
            dr_dn = ex * nx + ey * ny
            w = jw[p, q]
            ts = t_scale / dist * w
            t00 = ts * dr_dn * (a + 2.0 * ex * ex)
            t11 = ts * dr_dn * (a + 2.0 * ey * ey)
            skew = a * (ex * ny - nx * ey)
            t01 = ts * (dr_dn * 2.0 * ex * ey - skew)
            t10 = ts * (dr_dn * 2.0 * ex * ey + skew)
            log_factor = -math.log(dist / t[p, q]) - log_safe
            diag = log_coef * log_factor
            u00 = w * (scale * ex * ex + diag)
            u11 = w * (scale * ey * ey + diag)
            u01 = w * scale * ex * ey
            for k in range(n_loc):
                f = phi[p, q, k]
                fs = f - at_source[p, k]
                hb[0, k] += t00 * fs
                hb[1, k] += t01 * fs
                hb[2, k] += t10 * fs
                hb[3, k] += t11 * fs
                gb[0, k] += u00 * f
                gb[1, k] += u01 * f
                gb[2, k] += u11 * f
        for q in range(log_jw.shape[1]):
            w = log_coef * log_jw[p, q]
            for k in range(n_loc):
                f = w * log_phi[p, q, k]
                gb[0, k] += f
                gb[2, k] += f
        r0, r1 = 2 * s, 2 * s + 1
        for k in range(n_loc):
            c0 = 2 * cols[p, k]
            c1 = c0 + 1
            h[r0, c0] += hb[0, k]
            h[r0, c1] += hb[1, k]
            h[r1, c0] += hb[2, k]
            h[r1, c1] += hb[3, k]
            g[r0, c0] += gb[0, k]
            g[r0, c1] += gb[1, k]
            g[r1, c0] += gb[1, k]
            g[r1, c1] += gb[2, k]


@numba.njit(**_JIT)
def fill_mirrored(matrix, dofs, source, columns, sign):
    """:func:`fretbem.bem.mirror.fill`'s rows in one pass: matrix[dofs[r], c] =
    matrix[source[r], columns[c]] s_c s_(dofs[r]) (each s +-1: exact, the numpy path's
    numbers, signed zeros included)."""
    width = matrix.shape[1]
    for r in range(dofs.size):
        row, of = dofs[r], source[r]
        row_sign = sign[row]
        for c in range(width):
            matrix[row, c] = matrix[of, columns[c]] * sign[c] * row_sign


@numba.njit(**_JIT)
def row_sums(h, functions, n, out):
    """out[f, i, j] = the sum over b of h[2 f + i, 2 b + j] for each f in ``functions``, the
    terms added in order of b to 0 (the order of
    :func:`fretbem.bem.assembly._row_sums`, bit for bit), read in place: no gathered rows and
    no transposed chunks."""
    for p in range(functions.shape[0]):
        f = functions[p]
        for i in range(2):
            r = 2 * f + i
            s0, s1 = 0.0, 0.0  # numpy's sum starts from its identity (-0.0 + 0.0 is 0.0)
            for b in range(n):
                s0 += h[r, 2 * b]
                s1 += h[r, 2 * b + 1]
            out[f, i, 0] = s0
            out[f, i, 1] = s1
