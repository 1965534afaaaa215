"""Compiled (numba) critical-plane search: every criterion's planes in one pass per level.

The numpy search (:mod:`.critical_plane`) projects the stresses of every (step, point, plane)
into arrays and reduces them; here the loops compute each plane's normal and shear stresses
step by step and keep only their running maxima and minima, so no (step, point, plane) array
exists. The algorithm is the numpy search's, decision for decision: the best plane of the
coarse grid per criterion, the exact minimum circumscribed circle only where its bounds leave a
plane's rank open, the pattern search with halving steps (in-plane: the golden-section
search), the parabolic step. What differs is how, not what (the answers agree to round-off,
tests/framework/fatigue/test_search_compiled.py):

- the coarse grid is evaluated point by point (in-plane plane by plane for a block of points
  per call, the points vectorised: a call per point would pass and reference-count ~20
  arrays), in-plane in double precision, in 3D
  in single precision as numpy's (the chosen planes are evaluated again in double, as
  numpy's), row by row of psi; the extremes of the two shear components are taken once per
  theta and scaled (on a tilted plane they are in-plane quantities times factors >= 0 that
  do not depend on the step); exact ties go to the plane that comes first in the numpy
  search's grid;
- the coarse grid's exact circles are taken in decreasing order of the bound of each
  criterion's value and stop once no remaining plane can reach the best (numpy: every plane
  whose bound reaches the best lower bound); both find the plane of largest exact value;
- the refinement runs over blocks of points: every criterion's candidate planes of a level,
  for all the block's points, in one evaluation; it starts from the grid's quantities (in 3D
  evaluated again in double) and keeps the winning candidates' (numpy evaluates the start
  and the final planes again);
- a criterion whose search needs no shear (SWT, stress_life, strain_life) gets its final
  plane's shear amplitude here, by the bounds where they meet (a straight path) and its
  exact circle elsewhere (numpy: a projection and a circle per point after the search);
- neighbouring planes are reached by rotating the cosines and sines of the current plane, and
  a plane's circle starts from the support points of the plane it moved from (the circle is
  unique: only the number of rounds changes).

Functions are compiled on first use and cached on disk (``cache=True``), so a fresh process
pays numba's import and the cache load. Importing this module imports numba:
:mod:`.critical_plane` imports it only for searches large enough to repay it
(:func:`fretbem.fatigue.critical_plane.use_compiled`) or when asked to.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}
#: the plane loops: no NaN (the stresses are checked finite), fused multiply-adds; infinities
#: stay meaningful (the running extremes start at -inf and inf)
_LOOPS = {**_JIT, "fastmath": {"nnan", "contract", "nsz"}}

#: criterion codes (the order of :data:`fretbem.fatigue.critical_plane.METHODS`)
SWT, FINDLEY, FATEMI_SOCIE, MWCM, STRESS_LIFE, STRAIN_LIFE = range(6)
#: mean-stress correction kinds of stress_life: none, 1 - m/L (Goodman, Morrow), 1 - (m/L)^2
NO_CORRECTION, LINEAR, GERBER = range(3)
#: points per block of the refinement (the length of its vectorised loops)
BLOCK = 64
#: padding (doubles) of the rows of the work arrays: 5 cache lines, not a multiple of 4 KiB
_PAD = 40

_HALF_SQRT2 = 0.5 * math.sqrt(2.0)
_INSIDE = 1e-10  # as mcc.INSIDE_TOLERANCE
_ROUNDING = 1e-13  # as mcc.ROUNDING
_TIE = 1e-10  # as critical_plane.MWCM_TIE_TOLERANCE
_COS_HALF_PI = math.cos(0.5 * math.pi)  # the numpy search's cos(psi) at psi = 90 degrees
_GOLDEN = 0.3819660112501051  # as critical_plane.GOLDEN


# --------------------------------------------------------------------------- circles


@numba.njit(**_JIT)
def _circumcircle(px, py, qx, qy, rx, ry):
    bx, by = qx - px, qy - py
    cx, cy = rx - px, ry - py
    d = 2.0 * (bx * cy - by * cx)
    bb = bx * bx + by * by
    cc = cx * cx + cy * cy
    if not abs(d) > 1e-14 * max(max(bb, cc), 1e-300):
        return px, py, np.inf
    ux = (cy * bb - by * cc) / d
    uy = (bx * cc - cx * bb) / d
    return px + ux, py + uy, math.hypot(ux, uy)


@numba.njit(**_JIT)
def _encloses(x, y, sup, q, cx, cy, r):
    """Whether the circle (cx, cy, r) holds the support points and q (with the slack of
    :func:`fretbem.fatigue.mcc._smallest_with`)."""
    slack = _INSIDE * r + 1e-300
    for k in range(4):
        i = q if k == 3 else sup[k]
        if math.hypot(x[i] - cx, y[i] - cy) > r + slack:
            return False
    return True


@numba.njit(**_JIT)
def _smallest_with(x, y, sup, q):
    """Smallest circle of the support points ``sup`` (3 indices) and point ``q`` on its
    boundary (the candidates of :func:`fretbem.fatigue.mcc._smallest_with`, in its order);
    ``sup`` becomes the new support."""
    qx, qy = x[q], y[q]
    pick, bx, by, br = -1, 0.0, 0.0, np.inf
    for c in range(6):
        if c < 3:
            i = sup[c]
            ccx, ccy = 0.5 * (x[i] + qx), 0.5 * (y[i] + qy)
            cr = 0.5 * math.hypot(x[i] - qx, y[i] - qy)
        else:
            i, j = (
                (sup[0], sup[1]) if c == 3 else ((sup[0], sup[2]) if c == 4 else (sup[1], sup[2]))
            )
            ccx, ccy, cr = _circumcircle(x[i], y[i], x[j], y[j], qx, qy)
        if math.isfinite(cr) and cr < br and _encloses(x, y, sup, q, ccx, ccy, cr):
            pick, bx, by, br = c, ccx, ccy, cr
    if pick < 3:
        a = sup[pick]
        sup[0], sup[1] = a, a
    elif pick == 3:
        pass  # sup[0], sup[1] stay
    elif pick == 4:
        sup[1] = sup[2]
    else:
        sup[0], sup[1] = sup[1], sup[2]
    sup[2] = q
    return bx, by, br


@numba.njit(**_JIT)
def _circle(x, y, sup):
    """Radius of the smallest circle enclosing the points ``x``, ``y``: the support-set
    iteration of :func:`fretbem.fatigue.mcc.minimum_circumscribed_circle_xy`, one set.

    ``sup`` (3 indices) starts the iteration where ``sup[0] >= 0`` (the support of a nearby
    plane's path) and returns the support found."""
    m = x.size
    # round-off of the distances, of the coordinates' size (as mcc.ROUNDING)
    size_x = size_y = 0.0
    for i in range(m):
        size_x, size_y = max(size_x, abs(x[i])), max(size_y, abs(y[i]))
    rounding = _ROUNDING * (size_x + size_y) + 1e-300
    if min(sup[0], min(sup[1], sup[2])) < 0 or max(sup[0], max(sup[1], sup[2])) >= m:
        a, best = 0, -1.0
        for i in range(m):
            d = (x[i] - x[0]) ** 2 + (y[i] - y[0]) ** 2
            if d > best:
                a, best = i, d
        b, best = 0, -1.0
        for i in range(m):
            d = (x[i] - x[a]) ** 2 + (y[i] - y[a]) ** 2
            if d > best:
                b, best = i, d
        sup[0], sup[1], sup[2] = a, b, b
        cx, cy = 0.5 * (x[a] + x[b]), 0.5 * (y[a] + y[b])
        radius = 0.5 * math.sqrt(best)
    else:
        a, b, c = sup[0], sup[1], sup[2]
        cx, cy = 0.5 * (x[a] + x[b]), 0.5 * (y[a] + y[b])
        radius = 0.5 * math.hypot(x[a] - x[b], y[a] - y[b])
        if c != b and c != a:  # three supports: grow the circle of the first two by the third
            sup[2] = b
            if math.hypot(x[c] - cx, y[c] - cy) > radius * (1.0 + _INSIDE) + rounding:
                cx, cy, radius = _smallest_with(x, y, sup, c)
    for _ in range(200):
        far, dmax = 0, -1.0
        for i in range(m):
            d = (x[i] - cx) ** 2 + (y[i] - cy) ** 2
            if d > dmax:
                far, dmax = i, d
        if not math.sqrt(dmax) > radius * (1.0 + _INSIDE) + rounding:
            return radius
        cx, cy, radius = _smallest_with(x, y, sup, far)
    return radius


@numba.njit(**_JIT)
def _exact_tau(m, h, xy, zz, b, c2, s2, sp, cp, x, y, sup):
    """The exact shear amplitude of one plane of point ``b``: its path and its circle."""
    for t in range(x.size):
        ee = m[t, b] + h[t, b] * c2 + xy[t, b] * s2
        te = xy[t, b] * c2 - h[t, b] * s2
        x[t] = (sp * cp) * (ee - zz[t, b])
        y[t] = sp * te
    return _circle(x, y, sup)


@numba.njit(**_JIT)
def _plane_taus(m, h, xy, zz, nb, c2, s2, sp, cp, tau, x, y, sup, ext):
    """The shear amplitude of plane b of every point b of a block (``c2`` ... ``cp``, ``tau``:
    views of the block's planes, indexed from 0): half the extent of a straight path (its
    bounds within 1e-12, as the search takes them), else its exact circle. One call for the
    block, the steps outside and the points inside (a call per point passed and
    reference-counted seven arrays: ~7 % of the in-plane search in atomic reference counts,
    measured by perf). ``ext`` (8, nb) scratch."""
    hx, lx, hy, ly = ext[0, :nb], ext[1, :nb], ext[2, :nb], ext[3, :nb]
    hu, lu, hv, lv = ext[4, :nb], ext[5, :nb], ext[6, :nb], ext[7, :nb]
    for b in range(nb):
        hx[b] = hy[b] = hu[b] = hv[b] = -np.inf
        lx[b] = ly[b] = lu[b] = lv[b] = np.inf
    for t in range(m.shape[0]):
        mt, ht, xyt, zzt = m[t, :nb], h[t, :nb], xy[t, :nb], zz[t, :nb]
        for b in range(nb):
            ee = mt[b] + ht[b] * c2[b] + xyt[b] * s2[b]
            te = xyt[b] * c2[b] - ht[b] * s2[b]
            px, py = (sp[b] * cp[b]) * (ee - zzt[b]), sp[b] * te
            hx[b], lx[b], hy[b], ly[b] = max(hx[b], px), min(lx[b], px), max(hy[b], py), \
                min(ly[b], py)  # fmt: skip
            hu[b], lu[b] = max(hu[b], px + py), min(lu[b], px + py)
            hv[b], lv[b] = max(hv[b], px - py), min(lv[b], px - py)
    for b in range(nb):
        rx, ry = hx[b] - lx[b], hy[b] - ly[b]
        ru, rv = (hu[b] - lu[b]) * _HALF_SQRT2, (hv[b] - lv[b]) * _HALF_SQRT2
        lo = 0.5 * max(max(rx, ry), max(ru, rv))
        hi = 0.5 * math.sqrt(min(rx * rx + ry * ry, ru * ru + rv * rv))
        tau[b] = lo
        hx[b] = hi  # the points whose bounds part: their circle below
    for b in range(nb):
        if hx[b] > tau[b] * (1.0 + 1e-12):
            sup[0] = -1
            tau[b] = _exact_tau(m, h, xy, zz, b, c2[b], s2[b], sp[b], cp[b], x, y, sup)


# --------------------------------------------------------------------------- plane sums


@numba.njit(**_LOOPS)
def _reset(out, start, stop):
    for r in range(0, 12, 2):
        hi, lo = out[r, start:stop], out[r + 1, start:stop]  # views from 0 (:func:`_values`)
        for g in range(hi.size):
            hi[g], lo[g] = -np.inf, np.inf


@numba.njit(inline="always", **_LOOPS)  # called per point (3D: :func:`_coarse_3d`)
def _grid_summaries(m, h, xy, zz, tr, p, nu, c2, s2, axes, in_plane, out, scratch, rows=-1):
    """Running max / min over the steps of every grid plane at point ``p`` into ``out``
    (12, G): sigma_n, E eps_n and the shear extents (in-plane tau_e; 3D tau_1, tau_2, their
    sum and difference).

    In-plane the planes are ``c2``, ``s2`` (cos and sin 2theta). In 3D the grid is
    ``axes`` = (cos 2theta, sin 2theta (n_theta), sin psi, cos psi (n_psi)): plane
    ``j n_theta + i`` is (theta_i, psi_j), and the last plane is theta = psi = 0.
    sigma_ee and tau_e depend on theta alone and tau_1 = sin psi cos psi (sigma_ee - szz),
    tau_2 = sin psi tau_e scale them by factors >= 0: their extremes over the steps are
    taken per theta and scaled (exactly: rounding is monotone), once per row of psi. The 3D
    grid is summarised in single precision, as the numpy search's coarse grid: ``axes`` and
    ``scratch`` = (6, n_theta), (12, G) are float32, the summaries go to ``scratch[1]``.
    ``rows`` >= 0: the normal stress and strain of the first ``rows`` rows of psi and of the
    last plane only (the others' stay at -inf, inf: criteria convex in the tilt). The row
    sin psi = 1 (planes that contain z) leaves tau_1's round-off (cos psi ~ 6e-17) out of
    its sum and difference rows: they are +-tau_e's extremes, set after the steps.
    """
    a = 1.0 + nu
    n_t = m.shape[0]
    if in_plane:
        n_g = c2.size
        _reset(out, 0, n_g)
        o0, o1, o2, o3, o4, o5 = out[0, :n_g], out[1, :n_g], out[2, :n_g], out[3, :n_g], \
            out[4, :n_g], out[5, :n_g]  # fmt: skip
        for t in range(n_t):
            mt, ht, xyt, trt = m[t, p], h[t, p], xy[t, p], nu * tr[t, p]
            # one loop per pair of extremes: few arrays each, so that LLVM vectorises them
            for g in range(n_g):
                ee = mt + ht * c2[g] + xyt * s2[g]
                o0[g] = ee if ee > o0[g] else o0[g]
                o1[g] = ee if ee < o1[g] else o1[g]
            for g in range(n_g):
                en = a * (mt + ht * c2[g] + xyt * s2[g]) - trt
                o2[g] = en if en > o2[g] else o2[g]
                o3[g] = en if en < o3[g] else o3[g]
            for g in range(n_g):
                te = xyt * c2[g] - ht * s2[g]
                o4[g] = te if te > o4[g] else o4[g]
                o5[g] = te if te < o5[g] else o5[g]
        return
    s32, o32 = scratch
    _summaries_3d(m, h, xy, zz, tr, p, nu, axes[0], axes[1], axes[2], axes[3], s32[0], s32[1],
                  s32[2], s32[3], s32[4], s32[5], o32, rows)  # fmt: skip


@numba.njit(inline="always", **_JIT)  # per point: arrays made outside the points' loop
def _summaries_3d(m, h, xy, zz, tr, p, nu, tc2, ts2, psp, pcp, ee_t, te_t, d_hi, d_lo, te_hi,
                  te_lo, o32, rows):  # fmt: skip
    """The 3D branch of :func:`_grid_summaries` (its docstring) into ``o32`` (12, G), the
    axes and scratch rows passed one by one: no array view is made here (a view made per
    point is a reference count and its release, measured ~35 % of the 3D search)."""
    a = 1.0 + nu
    n_t = m.shape[0]
    n_th, n_ps = tc2.size, psp.size
    n_g = n_th * n_ps + 1
    for r in range(12):
        v = -np.inf if r % 2 == 0 else np.inf
        for g in range(n_g):
            o32[r, g] = v
    for i in range(n_th):
        d_hi[i], te_hi[i] = -np.inf, -np.inf
        d_lo[i], te_lo[i] = np.inf, np.inf
    last = n_g - 1
    a32, nu32 = np.float32(a), np.float32(nu)
    for t in range(n_t):
        mt, ht, xyt = np.float32(m[t, p]), np.float32(h[t, p]), np.float32(xy[t, p])
        zzt, trt = np.float32(zz[t, p]), nu32 * np.float32(tr[t, p])
        for i in range(n_th):
            ee = mt + ht * tc2[i] + xyt * ts2[i]
            te = xyt * tc2[i] - ht * ts2[i]
            ee_t[i], te_t[i] = ee, te
            d_hi[i], d_lo[i] = max(d_hi[i], ee - zzt), min(d_lo[i], ee - zzt)
            te_hi[i], te_lo[i] = max(te_hi[i], te), min(te_lo[i], te)
        for j in range(n_ps if rows < 0 else min(rows, n_ps)):
            sp2, cp2, spcp, spj = psp[j] * psp[j], pcp[j] * pcp[j], psp[j] * pcp[j], psp[j]
            row = j * n_th
            if spj == 1.0:  # planes that contain z: the shear rows after the steps (below)
                for i in range(n_th):
                    g = row + i
                    sn = sp2 * ee_t[i] + cp2 * zzt
                    en = a32 * sn - trt
                    o32[0, g] = max(o32[0, g], sn)
                    o32[1, g] = min(o32[1, g], sn)
                    o32[2, g] = max(o32[2, g], en)
                    o32[3, g] = min(o32[3, g], en)
                continue
            for i in range(n_th):
                g = row + i
                sn = sp2 * ee_t[i] + cp2 * zzt
                en = a32 * sn - trt
                px = spcp * (ee_t[i] - zzt)
                py = spj * te_t[i]
                o32[0, g] = max(o32[0, g], sn)
                o32[1, g] = min(o32[1, g], sn)
                o32[2, g] = max(o32[2, g], en)
                o32[3, g] = min(o32[3, g], en)
                o32[8, g] = max(o32[8, g], px + py)
                o32[9, g] = min(o32[9, g], px + py)
                o32[10, g] = max(o32[10, g], px - py)
                o32[11, g] = min(o32[11, g], px - py)
        # theta = psi = 0: the normal is z (sigma_n = szz, no shear on it)
        o32[0, last] = max(o32[0, last], zzt)
        o32[1, last] = min(o32[1, last], zzt)
        o32[2, last] = max(o32[2, last], a32 * zzt - trt)
        o32[3, last] = min(o32[3, last], a32 * zzt - trt)
    for j in range(n_ps):
        spcp, spj = psp[j] * pcp[j], psp[j]
        row = j * n_th
        for i in range(n_th):
            o32[4, row + i], o32[5, row + i] = spcp * d_hi[i], spcp * d_lo[i]
            o32[6, row + i], o32[7, row + i] = spj * te_hi[i], spj * te_lo[i]
            if spj == 1.0:  # tau_1 ~ cos psi is zero to round-off: tau_2 = tau_e alone
                o32[8, row + i], o32[9, row + i] = te_hi[i], te_lo[i]
                o32[10, row + i], o32[11, row + i] = -te_lo[i], -te_hi[i]
    for r in range(4, 12):
        o32[r, last] = 0.0


@numba.njit(inline="always", **_LOOPS)
def _plane_summaries_3d(m, h, xy, zz, tr, b, nu, c, s, sp, cp, shear, out, g):
    """:func:`_grid_summaries` of one 3D plane of point b into ``out[:, g]``, with the
    running extremes in registers (the loop over the steps stores nothing); without
    ``shear`` the normal stress and strain alone (rows 0-3: SWT, stress and strain life).

    A plane that contains z (sin psi = 1: most critical planes of a 2D model's stresses) has
    tau_2 = tau_e and tau_1, which carries cos psi (~6e-17), zero to round-off: its shear
    rows take tau_1 as 0, so the path is tau_e's segment and both bounds are half its range,
    as they are with the round-off tau_1 (the amplitude equal; tau_1 alone, a range ~1e-15
    of the stresses where tau_e is constant, is dropped)."""
    a = 1.0 + nu
    sp2, cp2, spcp = sp * sp, cp * cp, sp * cp
    hi0 = hi1 = hi2 = hi3 = hi4 = hi5 = -np.inf
    lo0 = lo1 = lo2 = lo3 = lo4 = lo5 = np.inf
    if shear and sp == 1.0:
        for t in range(m.shape[0]):
            ee = m[t, b] + h[t, b] * c + xy[t, b] * s
            te = xy[t, b] * c - h[t, b] * s
            sn = sp2 * ee + cp2 * zz[t, b]
            en = a * sn - nu * tr[t, b]
            hi0, lo0 = max(hi0, sn), min(lo0, sn)
            hi1, lo1 = max(hi1, en), min(lo1, en)
            hi3, lo3 = max(hi3, te), min(lo3, te)
        out[0, g], out[1, g], out[2, g], out[3, g] = hi0, lo0, hi1, lo1
        out[4, g], out[5, g], out[6, g], out[7, g] = 0.0, 0.0, hi3, lo3
        out[8, g], out[9, g], out[10, g], out[11, g] = hi3, lo3, -lo3, -hi3
        return
    if not shear:
        for t in range(m.shape[0]):
            sn = sp2 * (m[t, b] + h[t, b] * c + xy[t, b] * s) + cp2 * zz[t, b]
            en = a * sn - nu * tr[t, b]
            hi0, lo0 = max(hi0, sn), min(lo0, sn)
            hi1, lo1 = max(hi1, en), min(lo1, en)
        out[0, g], out[1, g], out[2, g], out[3, g] = hi0, lo0, hi1, lo1
        return
    for t in range(m.shape[0]):
        ee = m[t, b] + h[t, b] * c + xy[t, b] * s
        te = xy[t, b] * c - h[t, b] * s
        sn = sp2 * ee + cp2 * zz[t, b]
        en = a * sn - nu * tr[t, b]
        px = spcp * (ee - zz[t, b])
        py = sp * te
        hi0, lo0 = max(hi0, sn), min(lo0, sn)
        hi1, lo1 = max(hi1, en), min(lo1, en)
        hi2, lo2 = max(hi2, px), min(lo2, px)
        hi3, lo3 = max(hi3, py), min(lo3, py)
        hi4, lo4 = max(hi4, px + py), min(lo4, px + py)
        hi5, lo5 = max(hi5, px - py), min(lo5, px - py)
    out[0, g], out[1, g], out[2, g], out[3, g] = hi0, lo0, hi1, lo1
    out[4, g], out[5, g], out[6, g], out[7, g] = hi2, lo2, hi3, lo3
    out[8, g], out[9, g], out[10, g], out[11, g] = hi4, lo4, hi5, lo5


# inlined (numba IR, so compiled with the caller's flags: round-off moves, <1e-13): a call
# per criterion and point passed and reference-counted its arrays and views (3D: 3.10 -> 2.97x)
@numba.njit(inline="always", **_LOOPS)
def _shear_bounds(out, start, stop, in_plane, lo, hi):
    """Lower and upper bounds of each plane's shear amplitude (equal in-plane: a straight path),
    the rows as views indexed from 0 (:func:`_values`)."""
    x_hi, x_lo, y_hi, y_lo = out[4, start:stop], out[5, start:stop], out[6, start:stop], \
        out[7, start:stop]  # fmt: skip
    u_hi, u_lo, v_hi, v_lo = out[8, start:stop], out[9, start:stop], out[10, start:stop], \
        out[11, start:stop]  # fmt: skip
    lo, hi = lo[start:stop], hi[start:stop]
    if in_plane:
        for g in range(lo.size):
            lo[g] = 0.5 * (x_hi[g] - x_lo[g])
            hi[g] = lo[g]
        return
    for g in range(lo.size):
        rx = x_hi[g] - x_lo[g]
        ry = y_hi[g] - y_lo[g]
        ru = (u_hi[g] - u_lo[g]) * _HALF_SQRT2
        rv = (v_hi[g] - v_lo[g]) * _HALF_SQRT2
        lo[g] = 0.5 * max(max(rx, ry), max(ru, rv))
        hi[g] = 0.5 * math.sqrt(min(rx * rx + ry * ry, ru * ru + rv * rv))


@numba.njit(inline="always", **_LOOPS)  # inlined: as :func:`_shear_bounds`
def _values(code, par, E, out, tau, start, stop, value):
    """The parameter of criterion ``code`` on planes ``start:stop`` with shear amplitudes
    ``tau`` (``par``: k, yield strength, G, mean-stress correction kind, its limit).

    The rows are taken as views indexed from 0: an index ``start + g`` may be negative for
    numba, which wraps it around, and LLVM vectorises the wrapped index by gathers and
    scatters (measured slower than the contiguous loads and stores of a view)."""
    s_hi, s_lo, e_hi, e_lo = out[0, start:stop], out[1, start:stop], out[2, start:stop], \
        out[3, start:stop]  # fmt: skip
    t, v = tau[start:stop], value[start:stop]
    n = v.size
    if code == SWT:
        for g in range(n):
            v[g] = s_hi[g] * (0.5 * (e_hi[g] - e_lo[g]) / E)
    elif code == STRAIN_LIFE:
        for g in range(n):
            v[g] = 0.5 * (e_hi[g] - e_lo[g]) / E
    elif code == STRESS_LIFE:
        for g in range(n):
            amp, mean = 0.5 * (s_hi[g] - s_lo[g]), 0.5 * (s_hi[g] + s_lo[g])
            if par[3] == NO_CORRECTION:
                v[g] = amp + 0.0 * mean
                continue
            ratio = mean / par[4]
            factor = 1.0 - ratio * ratio if par[3] == GERBER else 1.0 - ratio
            v[g] = amp / factor if factor > 0.0 else np.inf
    elif code == FINDLEY:
        for g in range(n):
            v[g] = t[g] + par[0] * s_hi[g]
    elif code == FATEMI_SOCIE:
        for g in range(n):
            v[g] = (t[g] / par[2]) * (1.0 + par[0] * s_hi[g] / par[1])
    else:  # MWCM
        for g in range(n):
            v[g] = t[g]


@numba.njit(**_JIT)
def _needs_shear(code):
    return code == FINDLEY or code == FATEMI_SOCIE or code == MWCM


@numba.njit(**_JIT)
def _better(code, new, new2, old, old2, scale):
    if code != MWCM:
        return new > old
    tol = _TIE * scale
    return (new > old + tol) or ((new >= old - tol) and (new2 > old2))


# --------------------------------------------------------------------------- coarse grid


@numba.njit(**_JIT)
def _convex_in_tilt(code, par):
    """Whether criterion ``code`` is convex in sin^2 psi at every theta (strain life, stress
    life without a mean-stress correction): its 3D maximum is on psi = 0 or 90 degrees."""
    return code == STRAIN_LIFE or (code == STRESS_LIFE and par[3] == NO_CORRECTION)


@numba.njit(inline="always", **_LOOPS)
def _bounds_top(value, vhi, n):
    """``vhi`` becomes the larger of ``value`` and ``vhi`` (the value's upper bound, whichever
    way it varies with tau); returns the largest of the smaller ones (the best lower bound)."""
    top = -np.inf
    for g in range(n):
        a, b = value[g], vhi[g]
        vhi[g] = max(a, b)
        top = max(top, min(a, b))
    return top


@numba.njit(inline="always", **_LOOPS)
def _reaching(vhi, done, low, n, order):
    """The planes not ``done`` whose ``vhi`` reaches ``low``, into ``order``; their number."""
    count = 0
    for g in range(n):
        if not done[g] and vhi[g] >= low:
            order[count] = g
            count += 1
    return count


@numba.njit(inline="always", **_LOOPS)
def _first_at(value, top, rank, n):
    """The plane of ``value[:n]`` equal to ``top`` that comes first by ``rank``."""
    arg, first = 0, n
    for g in range(n):
        if value[g] == top and rank[g] < first:
            arg, first = g, rank[g]
    return arg


@numba.njit(inline="always", **_LOOPS)
def _best_tied(value, low, second, rank, n):
    """Of the planes whose ``value`` reaches ``low``, the one of largest ``second``, then the
    first by ``rank``."""
    arg, high, first = 0, -np.inf, n
    for g in range(n):
        if value[g] >= low and (second[g] > high or (second[g] == high and rank[g] < first)):
            arg, high, first = g, second[g], rank[g]
    return arg


@numba.njit(inline="always", **_LOOPS)
def _largest(value, n):
    """The largest of ``value[:n]`` (no NaN: a vectorised reduction)."""
    top = -np.inf
    for g in range(n):
        top = max(top, value[g])
    return top


@numba.njit(inline="always", **_LOOPS)
def _value_at(code, k, sy, shear_modulus, kind, limit, E, s_hi, s_lo, e_hi, e_lo, tau):
    """:func:`_values` of one plane from its summaries and the criterion's constants (``par``
    row: k, yield strength, G, mean-stress correction kind, its limit), scalars only: no
    array is passed (and reference-counted)."""
    if code == SWT:
        return s_hi * (0.5 * (e_hi - e_lo) / E)
    if code == STRAIN_LIFE:
        return 0.5 * (e_hi - e_lo) / E
    if code == STRESS_LIFE:
        amp, mean = 0.5 * (s_hi - s_lo), 0.5 * (s_hi + s_lo)
        if kind == NO_CORRECTION:
            return amp + 0.0 * mean
        ratio = mean / limit
        factor = 1.0 - ratio * ratio if kind == GERBER else 1.0 - ratio
        return amp / factor if factor > 0.0 else np.inf
    if code == FINDLEY:
        return tau + k * s_hi
    if code == FATEMI_SOCIE:
        return (tau / shear_modulus) * (1.0 + k * s_hi / sy)
    return tau  # MWCM


@numba.njit(inline="always", **_LOOPS)
def _grid_values(code, k, sy, shear_modulus, kind, limit, E, n, s_hi, s_lo, e_rng, tau, value):
    """:func:`_value_at` of ``n`` planes from their summaries (``e_rng``: the range of E eps_n),
    the criterion's test outside the loops, so that each loop vectorises."""
    if code == SWT:
        for i in range(n):
            value[i] = s_hi[i] * (0.5 * e_rng[i] / E)
    elif code == STRAIN_LIFE:
        for i in range(n):
            value[i] = 0.5 * e_rng[i] / E
    elif code == STRESS_LIFE:
        for i in range(n):
            value[i] = _value_at(code, k, sy, shear_modulus, kind, limit, E, s_hi[i], s_lo[i],
                                 0.0, 0.0, 0.0)  # fmt: skip
    elif code == FINDLEY:
        for i in range(n):
            value[i] = tau[i] + k * s_hi[i]
    elif code == FATEMI_SOCIE:
        for i in range(n):
            value[i] = (tau[i] / shear_modulus) * (1.0 + k * s_hi[i] / sy)
    else:  # MWCM
        for i in range(n):
            value[i] = tau[i]


@numba.njit(**_LOOPS)
def _coarse_in_plane(m, h, xy, tr, p0, nb, nu, c2, s2, codes, par, E, best, found):
    """:func:`_coarse_3d` of the in-plane grid for points ``p0:p0 + nb`` of the step data, into
    ``best`` (C nb) and ``found`` (7, C nb) at ``ci nb + b``: the summaries, each criterion's
    best plane (no circles: the shear paths are straight) and its grid neighbours' values.

    Plane by plane, the steps outside and the block's points inside (vectorised, as the
    golden refinement), only the extremes the criteria's values read, in one loop; each
    criterion's best plane per point by running selects over the planes
    (vectorised over the points). ``found[3]`` (sigma_n min) and ``found[4]`` (the strain
    amplitude) are NaN unless a requested criterion's value reads them: the refinement takes
    them on its final planes (:func:`_golden_in_plane`).

    The grid is in the numpy search's order (``rank`` is the identity): an exact tie goes to
    the first plane that has the largest value."""
    a = 1.0 + nu
    n_t, n_g, n_c = m.shape[0], c2.size, codes.size
    need_lo, need_strain, need_shear = False, False, False
    for ci in range(n_c):
        code = codes[ci]
        need_lo = need_lo or code == STRESS_LIFE
        need_strain = need_strain or code == SWT or code == STRAIN_LIFE
        need_shear = need_shear or _needs_shear(code)
    n = n_g * nb
    # (plane, point) rows: sigma_n max, min, the range of E eps_n, the shear amplitude, the
    # value; the running extremes of a plane; nu tr per step and point
    rows = np.empty((5, n + _PAD))
    s_hi, s_lo, e_rng, g_tau, g_val = rows[0, :n], rows[1, :n], rows[2, :n], rows[3, :n], \
        rows[4, :n]  # fmt: skip
    # the same rows as (plane, point): indexed [g, b], no view per plane (a view is an atomic
    # reference count and its release: ~15 % of the in-plane search in NRT_incref/decref)
    sh, sl, er, gt = s_hi.reshape((n_g, nb)), s_lo.reshape((n_g, nb)), \
        e_rng.reshape((n_g, nb)), g_tau.reshape((n_g, nb))  # fmt: skip
    gv, sh2 = g_val.reshape((n_g, nb)), sh
    ext = np.empty((4, nb + _PAD))
    e_hi, e_lo, t_hi, t_lo = ext[0, :nb], ext[1, :nb], ext[2, :nb], ext[3, :nb]
    ntr = np.empty((n_t, nb))
    for t in range(n_t):
        for b in range(nb):
            ntr[t, b] = nu * tr[t, p0 + b]
    for g in range(n_g):
        c, s = c2[g], s2[g]
        # the extremes the criteria read in one loop over the steps and points (measured
        # 2.4 times faster than a loop per extreme here: the step data is read once); the
        # tests outside the loops, so that each loop vectorises
        for b in range(nb):
            sh[g, b], e_hi[b], t_hi[b] = -np.inf, -np.inf, -np.inf
            sl[g, b], e_lo[b], t_lo[b] = np.inf, np.inf, np.inf
        if need_strain and need_shear:
            for t in range(n_t):
                for b in range(nb):
                    p = p0 + b
                    ee = m[t, p] + h[t, p] * c + xy[t, p] * s
                    en = a * (m[t, p] + h[t, p] * c + xy[t, p] * s) - ntr[t, b]
                    te = xy[t, p] * c - h[t, p] * s
                    sh[g, b] = max(sh[g, b], ee)
                    e_hi[b], e_lo[b] = max(e_hi[b], en), min(e_lo[b], en)
                    t_hi[b], t_lo[b] = max(t_hi[b], te), min(t_lo[b], te)
        elif need_shear:
            for t in range(n_t):
                for b in range(nb):
                    p = p0 + b
                    ee = m[t, p] + h[t, p] * c + xy[t, p] * s
                    te = xy[t, p] * c - h[t, p] * s
                    sh[g, b] = max(sh[g, b], ee)
                    t_hi[b], t_lo[b] = max(t_hi[b], te), min(t_lo[b], te)
        elif need_strain:
            for t in range(n_t):
                for b in range(nb):
                    p = p0 + b
                    ee = m[t, p] + h[t, p] * c + xy[t, p] * s
                    en = a * (m[t, p] + h[t, p] * c + xy[t, p] * s) - ntr[t, b]
                    sh[g, b] = max(sh[g, b], ee)
                    e_hi[b], e_lo[b] = max(e_hi[b], en), min(e_lo[b], en)
        else:
            for t in range(n_t):
                for b in range(nb):
                    p = p0 + b
                    ee = m[t, p] + h[t, p] * c + xy[t, p] * s
                    sh[g, b] = max(sh[g, b], ee)
        if need_lo:  # a loop of its own: with the others, measured slower (6 extremes)
            for t in range(n_t):
                for b in range(nb):
                    p = p0 + b
                    ee = m[t, p] + h[t, p] * c + xy[t, p] * s
                    sl[g, b] = min(sl[g, b], ee)
        for b in range(nb):
            er[g, b] = e_hi[b] - e_lo[b]
            gt[g, b] = 0.5 * (t_hi[b] - t_lo[b])  # a straight path: half its range
    arg = np.empty(nb, dtype=np.int64)
    for ci in range(n_c):
        code = codes[ci]
        _grid_values(code, par[ci, 0], par[ci, 1], par[ci, 2], par[ci, 3], par[ci, 4], E, n,
                     s_hi, s_lo, e_rng, g_tau, g_val)  # fmt: skip
        top = e_hi  # the best value per point so far
        for b in range(nb):
            top[b], arg[b] = g_val[b], 0
        for g in range(1, n_g):  # the first plane of the largest value
            for b in range(nb):
                v = gv[g, b]
                up = v > top[b]
                top[b] = v if up else top[b]
                arg[b] = g if up else arg[b]
        if code == MWCM:  # ties within the tolerance: the largest normal stress, the first
            low, high = e_lo, top
            for b in range(nb):
                low[b] = top[b] - _TIE * max(abs(top[b]), 1e-300)
                high[b], arg[b] = -np.inf, 0
            for g in range(n_g):
                for b in range(nb):
                    up = (gv[g, b] >= low[b]) & (sh2[g, b] > high[b])
                    high[b] = sh2[g, b] if up else high[b]
                    arg[b] = g if up else arg[b]
        shear = _needs_shear(code)
        for b in range(nb):
            j, i = arg[b] * nb + b, ci * nb + b
            best[i] = arg[b]
            found[0, i] = g_val[j]
            found[1, i] = g_tau[j] if shear else 0.0
            found[2, i] = s_hi[j]
            found[3, i] = s_lo[j] if need_lo else np.nan
            found[4, i] = 0.5 * e_rng[j] / E if need_strain else np.nan
            # the values of its grid neighbours (the golden-section bracket's ends)
            found[5, i] = g_val[(arg[b] - 1 if arg[b] > 0 else n_g - 1) * nb + b]
            found[6, i] = g_val[(arg[b] + 1 if arg[b] < n_g - 1 else 0) * nb + b]


@numba.njit(inline="always", **_JIT)
def _values_3d(code, k, sy, shear_modulus, kind, limit, E, o32, t, n, v):
    """:func:`_value_at` of the grid planes ``0:n`` from the summaries ``o32`` and shear
    amplitudes ``t`` into ``v``, the criterion's test outside the loops so that each loop
    vectorises (the same expressions: the same numbers)."""
    if code == SWT:
        for g in range(n):
            v[g] = o32[0, g] * (0.5 * (o32[2, g] - o32[3, g]) / E)
    elif code == STRAIN_LIFE:
        for g in range(n):
            v[g] = 0.5 * (o32[2, g] - o32[3, g]) / E
    elif code == STRESS_LIFE:
        for g in range(n):
            v[g] = _value_at(code, k, sy, shear_modulus, kind, limit, E, o32[0, g], o32[1, g],
                             o32[2, g], o32[3, g], t[g])  # fmt: skip
    elif code == FINDLEY:
        for g in range(n):
            v[g] = t[g] + k * o32[0, g]
    elif code == FATEMI_SOCIE:
        for g in range(n):
            v[g] = (t[g] / shear_modulus) * (1.0 + k * o32[0, g] / sy)
    else:  # MWCM
        for g in range(n):
            v[g] = t[g]


@numba.njit(**_JIT)  # the search's flags: its summaries' float32 round-off, its choices
def _coarse_3d(data, nb, grid, axes, rank, codes, par, nu, E, work, scratch, best, found, sup,
               select=True):  # fmt: skip
    """The best 3D grid plane of every criterion at each point b of a block of ``nb`` points of
    the step data, into ``best`` (C nb) and its quantities (value, tau, sigma_n max and min,
    normal strain amplitude) into ``found`` (5+, C nb), at ``ci nb + b``; the grid circles as
    the module docstring says. ``select`` False: the summaries alone (a benchmark's phase).

    Point by point, every array made before the points' loop, the per-plane values by loops
    that make no view (:func:`_values_3d`): a view made per point and criterion (the rows of the
    summaries, ``par[ci]``) was a reference count and its release each, ~35 % of the 3D
    search in ``NRT_incref``/``NRT_decref`` (perf)."""
    m, h, xy, zz, tr, x, y = data
    _, lo, hi, tau, value, _, vhi, done, order = work
    tc2, ts2, psp, pcp = axes  # single precision (:func:`_grid_summaries`)
    s32, o32 = scratch
    ee_t, te_t, d_hi, d_lo, te_hi, te_lo = s32[0], s32[1], s32[2], s32[3], s32[4], s32[5]
    c2, s2, sp, cp = grid[0], grid[1], grid[2], grid[3]
    n_g, n_c = grid.shape[1], codes.size
    flat = True  # every criterion convex in the tilt: the in-plane row and psi = 0
    shear = False
    for ci in range(n_c):
        flat = flat and _convex_in_tilt(codes[ci], par[ci])
        shear = shear or _needs_shear(codes[ci])
    rows = 1 if flat else -1
    n_row = 1  # the first row of psi (sin psi = 1): a convex criterion's candidates
    while n_row < n_g - 1 and sp[n_row] == sp[0]:
        n_row += 1
    for b in range(nb):
        _summaries_3d(m, h, xy, zz, tr, b, nu, tc2, ts2, psp, pcp, ee_t, te_t, d_hi, d_lo,
                      te_hi, te_lo, o32, rows)  # fmt: skip
        if not select:
            continue
        n_open_grid = 0  # planes whose circle is open (bounds apart): none, no circle to rank
        if shear:  # :func:`_shear_bounds`, float32 ranges as there
            for g in range(n_g):
                rx = o32[4, g] - o32[5, g]
                ry = o32[6, g] - o32[7, g]
                ru = (o32[8, g] - o32[9, g]) * _HALF_SQRT2
                rv = (o32[10, g] - o32[11, g]) * _HALF_SQRT2
                lo[g] = 0.5 * max(max(rx, ry), max(ru, rv))
                hi[g] = 0.5 * math.sqrt(min(rx * rx + ry * ry, ru * ru + rv * rv))
                tau[g] = lo[g]
                done[g] = not hi[g] > lo[g] * (1.0 + 1e-12)
                n_open_grid += 0 if done[g] else 1
        for ci in range(n_c):
            code = codes[ci]
            k, sy, shear_modulus, kind, limit = par[ci, 0], par[ci, 1], par[ci, 2], \
                par[ci, 3], par[ci, 4]  # fmt: skip
            if code == STRAIN_LIFE or (code == STRESS_LIFE and kind == NO_CORRECTION):
                # convex in the tilt (:func:`_convex_in_tilt`): its maximum is on the in-plane
                # row (sin psi = 1) or the plane normal to z (docs/explanation/fatigue.md)
                _values_3d(code, k, sy, shear_modulus, kind, limit, E, o32, tau, n_g, value)
                for g in range(n_row, n_g - 1):
                    value[g] = -np.inf
            elif n_open_grid and _needs_shear(code):
                # exact circles in decreasing order of the value's upper bound, while it can
                # win; ``value`` at ``tau``: the lower bound, or the circle another criterion
                # took; ``vhi`` the larger of the values at the bounds
                _values_3d(code, k, sy, shear_modulus, kind, limit, E, o32, tau, n_g, value)
                _values_3d(code, k, sy, shear_modulus, kind, limit, E, o32, hi, n_g, vhi)
                top = -np.inf  # the best lower bound
                for g in range(n_g):
                    v, w = value[g], vhi[g]
                    vhi[g] = max(v, w)
                    top = max(top, min(v, w))
                slack = _TIE * abs(top) if code == MWCM else 0.0
                # the planes whose bound reaches the best lower bound, open ones first
                n_open = 0
                for g in range(n_g):
                    if not done[g] and vhi[g] >= top - slack:
                        order[n_open] = g
                        n_open += 1
                while n_open:
                    pick = 0
                    for i in range(1, n_open):
                        if vhi[order[i]] > vhi[order[pick]]:
                            pick = i
                    arg = order[pick]
                    slack = _TIE * abs(top) if code == MWCM else 0.0
                    if not vhi[arg] >= top - slack:
                        break
                    n_open -= 1
                    order[pick] = order[n_open]
                    sup[0] = -1
                    tau[arg] = _exact_tau(
                        m, h, xy, zz, b, c2[arg], s2[arg], sp[arg], cp[arg], x, y, sup
                    )
                    done[arg] = True
                    value[arg] = _value_at(code, k, sy, shear_modulus, kind, limit, E,
                                           o32[0, arg], o32[1, arg], o32[2, arg], o32[3, arg],
                                           tau[arg])  # fmt: skip
                    top = max(top, value[arg])
            else:
                _values_3d(code, k, sy, shear_modulus, kind, limit, E, o32, tau, n_g, value)
            # exact ties (infinite stress_life values, symmetric states) go to the plane that
            # comes first in the numpy search's grid order, ``rank``: the largest value first,
            # then the first plane that has it (MWCM: of those within the tolerance, the
            # largest normal stress, then the first)
            top = -np.inf
            for g in range(n_g):
                top = max(top, value[g])
            arg = 0
            if code == MWCM:
                low, high, first = top - _TIE * max(abs(top), 1e-300), -np.inf, n_g
                for g in range(n_g):
                    s_hi = o32[0, g]
                    if value[g] >= low and (s_hi > high or (s_hi == high and rank[g] < first)):
                        arg, high, first = g, s_hi, rank[g]
            else:
                first = n_g
                for g in range(n_g):
                    if value[g] == top and rank[g] < first:
                        arg, first = g, rank[g]
            i = ci * nb + b
            best[i] = arg
            found[0, i] = value[arg]
            found[1, i] = tau[arg] if _needs_shear(code) else 0.0
            found[2, i] = o32[0, arg]
            found[3, i] = o32[1, arg]
            found[4, i] = 0.5 * (o32[2, arg] - o32[3, arg]) / E


# --------------------------------------------------------------------------- refinement


@numba.njit(**_JIT)
def _cos_sin(x):
    """cos x, sin x; Taylor series below 0.1 (exact to round-off there), libm above."""
    if abs(x) >= 0.1:
        return math.cos(x), math.sin(x)
    x2 = x * x
    c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0)))
    s = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))))
    return c, s


#: Taylor coefficients of cos x and of (sin x - x) / x in x^2, to x^10: exact to round-off
#: below 0.1, as :func:`_cos_sin`'s series, by products alone (a division costs ~10 cycles
#: of throughput: the golden search turns every point's plane at every iteration)
_C0, _C1, _C2, _C3, _C4 = -1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0
_S0, _S1, _S2, _S3, _S4 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0


@numba.njit(**_JIT)
def _evaluate(data, nb, planes, n_rep, per, codes, par, nu, E, against, cur, work, exact,
              keep=None, bounded=None):  # fmt: skip
    """Quantities and values of ``n_rep`` planes per point of a block of ``nb`` points; plane
    ``r nb + b`` is point b's, of criterion ``r // per``. With ``against``, a plane that cannot
    beat its criterion's current value keeps the lower bound of its shear amplitude (the numpy
    search's ``_SharedPass._exact``); the exact circles start from the current plane's support.
    ``keep`` (3D): the planes g where it is True are not evaluated; the caller sets their
    values. ``exact`` (bool, one per plane) out: whether a plane's shear amplitude is its
    exact one (bounds that meet, or its circle), not a bound. ``bounded`` (without
    ``against``): the planes that keep the bound, as ``against`` says, where it is True.
    """
    m, h, xy, zz, tr, x, y = data
    c2, s2, sp, cp, psup = planes
    out, lo, hi, tau, value, vlo, vhi, _, _ = work
    cvalue, cscale, csup = cur
    for r in range(n_rep):
        shear = _needs_shear(codes[r // per])
        for b in range(nb):
            g = r * nb + b
            if keep is None or not keep[g]:
                _plane_summaries_3d(m, h, xy, zz, tr, b, nu, c2[g], s2[g], sp[g], cp[g], shear,
                                    out, g)  # fmt: skip
    for ci in range(codes.size):
        code = codes[ci]
        start, stop = ci * per * nb, (ci + 1) * per * nb
        if _needs_shear(code):
            _shear_bounds(out, start, stop, False, lo, hi)
            for g in range(start, stop):
                if keep is None or not keep[g]:
                    tau[g] = lo[g]
            if against or bounded is not None:
                _values(code, par[ci], E, out, lo, start, stop, vlo)
                _values(code, par[ci], E, out, hi, start, stop, vhi)
            for g in range(start, stop):
                if keep is not None and keep[g]:
                    continue
                exact[g] = True
                if not hi[g] > lo[g] * (1.0 + 1e-12):
                    psup[g, 0] = -1
                    continue
                b = g % nb
                k = ci * nb + b
                if against or (bounded is not None and bounded[g]):
                    slack = _TIE * cscale[k] if code == MWCM else 0.0
                    if not max(vlo[g], vhi[g]) >= cvalue[k] - slack:
                        psup[g, 0] = -1
                        exact[g] = False
                        continue
                psup[g, 0], psup[g, 1], psup[g, 2] = csup[k, 0], csup[k, 1], csup[k, 2]
                tau[g] = _exact_tau(m, h, xy, zz, b, c2[g], s2[g], sp[g], cp[g], x, y, psup[g])
        else:
            for g in range(start, stop):
                tau[g] = 0.0
                exact[g] = True
        _values(code, par[ci], E, out, tau, start, stop, value)


@numba.njit(**_JIT)
def _parabola(v_lo, centre, v_hi, h):
    """The step to the vertex of the parabola through v_lo, centre, v_hi at -h, 0, h; none
    where it opens upwards, at most h (the numpy search's where, nan_to_num and clip)."""
    curv = v_lo - 2.0 * centre + v_hi
    d = 0.0
    if curv < 0:
        d = 0.5 * h * (v_lo - v_hi) / curv
    if math.isnan(d):
        d = 0.0
    return min(max(d, -h), h)


@numba.njit(**_JIT)
def _moved(c2, s2, sp, cp, psi, dt, dp, turn):
    """cos 2theta, sin 2theta, sin psi, cos psi, psi of the plane turned by (dt, dp); psi is
    clipped to [0, pi/2] as the numpy search clips it. ``turn``: cos 2dt, sin 2dt, cos dp,
    sin dp."""
    nc2, ns2 = c2, s2
    if dt != 0.0:
        nc2, ns2 = c2 * turn[0] - s2 * turn[1], s2 * turn[0] + c2 * turn[1]
    if dp == 0.0:
        return nc2, ns2, sp, cp, psi
    npsi = psi + dp
    if npsi >= 0.5 * np.pi:
        return nc2, ns2, 1.0, _COS_HALF_PI, 0.5 * np.pi
    if npsi <= 0.0:
        return nc2, ns2, 0.0, 1.0, 0.0
    return nc2, ns2, sp * turn[2] + cp * turn[3], cp * turn[2] - sp * turn[3], npsi


@numba.njit(**_JIT)
def _turn(dt, dp, turn):
    """cos 2dt, sin 2dt, cos dp, sin dp into ``turn``."""
    turn[0], turn[1] = _cos_sin(2.0 * dt)
    turn[2], turn[3] = _cos_sin(dp)


@numba.njit(**_JIT)
def _keep(cres, i, value, tau, out, g, E):
    """The quantities of evaluated plane ``g`` as current plane ``i``'s."""
    cres[0, i] = value[g]
    cres[1, i] = tau[g]
    cres[2, i] = out[0, g]
    cres[3, i] = out[1, g]
    cres[4, i] = 0.5 * (out[2, g] - out[3, g]) / E


@numba.njit(**_JIT)
def _refine_block(data, nb, cur_planes, cur_angles, cur, cres, cand, cand_angles, codes, par,
                  nu, E, steps, levels, work, exact):  # fmt: skip
    """The numpy search's ``_refine`` for a block of points: every criterion's candidates of a
    level in one :func:`_evaluate`. ``cres`` (5, C nb): the current planes' quantities (value,
    tau, sigma_n max and min, normal strain amplitude), from the grid in, the final ones out:
    a plane that wins has its exact circle (one that cannot win keeps a bound, never wins).

    In 3D, a neighbour that is the plane itself (on the boundaries psi = 0 and 90 degrees)
    takes the plane's value unevaluated. The last level halves no step: where a plane did not
    move at the level before, its neighbours are that level's, and their values (where exact:
    the parabolic step reads them) are taken as they are; where it moved in theta, the
    neighbour back is the plane it left, whose exact value is known (the same plane to
    round-off; not so in psi, where a move may have been clipped at a boundary). There,
    too, a boundary plane's tilted neighbour keeps its bound where it cannot beat the plane:
    below the plane's value, the parabolic step in psi clips back to the boundary whatever
    it is. ``exact`` (bool, C 4 nb): :func:`_evaluate`'s."""
    c2, s2, sp, cp, csup = cur_planes
    th, ps = cur_angles
    cvalue, cscale, _ = cur
    second = np.empty(cvalue.size)
    left = np.empty(cvalue.size)  # the value of the plane left at the level before
    moved = np.empty(cvalue.size, dtype=np.int64)  # the slot it moved to then, or -1
    same = np.empty(exact.size, dtype=np.bool_)  # a neighbour that is the plane itself
    tilted = np.empty(exact.size, dtype=np.bool_)  # the other neighbour in psi of such a one
    keep = work[7]
    turn = np.empty(4)
    n_c = codes.size
    k = 4
    out = work[0]
    value = work[4]
    # the start planes: the coarse grid's exact quantities (``cres``, kept up to date below)
    for i in range(n_c * nb):
        csup[i, 0] = -1
        cvalue[i] = cres[0, i]
        second[i] = cres[2, i]
        cscale[i] = max(abs(cvalue[i]), 1e-300)
    q2, qs2, qsp, qcp, qsup = cand
    qth, qps = cand_angles
    for level in range(levels + 1):
        last = level == levels
        again = last and levels > 0  # the step of the level before: its neighbours again
        ht = steps[0] / 2 ** min(level + 1, levels)
        hp = steps[1] / 2 ** min(level + 1, levels)
        for ci in range(n_c):
            for j in range(k):
                dt = (-ht if j == 0 else ht) if j < 2 else 0.0
                dp = 0.0 if j < 2 else (-hp if j == 2 else hp)
                _turn(dt, dp, turn)
                for b in range(nb):
                    i = ci * nb + b
                    g = (ci * k + j) * nb + b
                    q2[g], qs2[g], qsp[g], qcp[g], qps[g] = _moved(
                        c2[i], s2[i], sp[i], cp[i], ps[i], dt, dp, turn
                    )
                    qth[g] = th[i] + dt
        # not evaluated: a neighbour that is the plane itself (psi = 90 degrees: psi + hp;
        # psi = 0, the normal z: every neighbour but psi + hp), and on the last level the
        # level before's exact neighbours of a plane that stayed, and the plane it left in theta
        for ci in range(n_c):
            for j in range(k):
                for b in range(nb):
                    i, g = ci * nb + b, (ci * k + j) * nb + b
                    same[g] = ps[i] >= 0.5 * np.pi if j == 3 else ps[i] <= 0.0
                    tilted[g] = ps[i] >= 0.5 * np.pi if j == 2 else (j == 3 and ps[i] <= 0.0)
                    keep[g] = same[g] or (again and moved[i] < 0 and exact[g])
                    keep[g] = keep[g] or (again and j < 2 and moved[i] == j ^ 1)
        _evaluate(data, nb, cand, n_c * k, k, codes, par, nu, E, not last, cur, work, exact,
                  keep, tilted)  # fmt: skip
        for ci in range(n_c):
            for j in range(k):
                for b in range(nb):
                    i, g = ci * nb + b, (ci * k + j) * nb + b
                    if same[g]:
                        value[g], out[0, g] = cvalue[i], second[i]  # never wins
                    elif again and j < 2 and moved[i] == j ^ 1:
                        value[g] = left[i]  # the last level reads the values alone
        for i in range(n_c * nb):
            moved[i] = -1
        if not last:
            for ci in range(n_c):
                code = codes[ci]
                for b in range(nb):
                    i = ci * nb + b
                    arg = (ci * k) * nb + b
                    for j in range(1, k):
                        g = (ci * k + j) * nb + b
                        if value[g] > value[arg]:
                            arg = g
                    if code == MWCM:
                        tol = _TIE * max(abs(value[arg]), 1e-300)
                        top, arg = value[arg], -1
                        for j in range(k):
                            g = (ci * k + j) * nb + b
                            if value[g] >= top - tol and (arg < 0 or out[0, g] > out[0, arg]):
                                arg = g
                    if _better(code, value[arg], out[0, arg], cvalue[i], second[i], cscale[i]):
                        moved[i], left[i] = (arg - b) // nb - ci * k, cvalue[i]
                        th[i], ps[i] = qth[arg], qps[arg]
                        c2[i], s2[i], sp[i], cp[i] = q2[arg], qs2[arg], qsp[arg], qcp[arg]
                        cvalue[i], second[i] = value[arg], out[0, arg]
                        _keep(cres, i, value, work[3], out, arg, E)
                        if qsup[arg, 0] >= 0:
                            csup[i, 0], csup[i, 1], csup[i, 2] = (
                                qsup[arg, 0],
                                qsup[arg, 1],
                                qsup[arg, 2],
                            )
            continue
        # one parabolic step per angle through the last level's three values
        for ci in range(n_c):
            for b in range(nb):
                i = ci * nb + b
                g0 = (ci * k) * nb + b
                dt = _parabola(value[g0], cvalue[i], value[g0 + nb], ht)
                dp = _parabola(value[g0 + 2 * nb], cvalue[i], value[g0 + 3 * nb], hp)
                _turn(dt, dp, turn)
                q2[i], qs2[i], qsp[i], qcp[i], qps[i] = _moved(
                    c2[i], s2[i], sp[i], cp[i], ps[i], dt, dp, turn
                )
                qth[i] = th[i] + dt
        _evaluate(data, nb, cand, n_c, 1, codes, par, nu, E, True, cur, work, exact)
        for ci in range(n_c):
            for b in range(nb):
                i = ci * nb + b
                if _better(codes[ci], value[i], out[0, i], cvalue[i], second[i], cscale[i]):
                    _keep(cres, i, value, work[3], out, i, E)
                    th[i], ps[i] = qth[i], qps[i]
                    c2[i], s2[i], sp[i], cp[i] = q2[i], qs2[i], qsp[i], qcp[i]
                    if qsup[i, 0] >= 0:
                        csup[i, 0], csup[i, 1], csup[i, 2] = qsup[i, 0], qsup[i, 1], qsup[i, 2]


@numba.njit(inline="always", **_LOOPS)
def _extreme_normal(m, h, xy, nb, c2, s2, start, o, upper):
    """Running max (``upper``) or min over the steps of sigma_n on planes ``start:start + nb``
    (plane ``start + b`` of point b) into ``o``: the steps outside, the points inside (one
    array written per loop, so that LLVM vectorises it; views indexed from 0, as
    :func:`_values`)."""
    o, c2, s2 = o[start : start + nb], c2[start : start + nb], s2[start : start + nb]
    for b in range(nb):
        o[b] = -np.inf if upper else np.inf
    if upper:  # the test outside the loops: LLVM does not unswitch every loop
        for t in range(m.shape[0]):
            for b in range(nb):
                ee = m[t, b] + h[t, b] * c2[b] + xy[t, b] * s2[b]
                o[b] = ee if ee > o[b] else o[b]
        return
    for t in range(m.shape[0]):
        for b in range(nb):
            ee = m[t, b] + h[t, b] * c2[b] + xy[t, b] * s2[b]
            o[b] = ee if ee < o[b] else o[b]


@numba.njit(inline="always", **_LOOPS)
def _final_extremes(m, h, xy, tr, nb, nu, c2, s2, start, out):
    """sigma_n's minimum and E eps_n's maximum and minimum on planes ``start:start + nb``
    into rows 1-3 of ``out`` in one loop over the steps and points (the expressions and
    selects of :func:`_extreme_normal` and E eps_n's likewise: the same numbers, the step
    data read once)."""
    a = 1.0 + nu
    stop = start + nb
    s_lo, e_hi, e_lo = out[1, start:stop], out[2, start:stop], out[3, start:stop]
    c2, s2 = c2[start:stop], s2[start:stop]
    for b in range(nb):
        s_lo[b], e_hi[b], e_lo[b] = np.inf, -np.inf, np.inf
    for t in range(m.shape[0]):
        for b in range(nb):
            ee = m[t, b] + h[t, b] * c2[b] + xy[t, b] * s2[b]
            en = a * (m[t, b] + h[t, b] * c2[b] + xy[t, b] * s2[b]) - nu * tr[t, b]
            s_lo[b] = ee if ee < s_lo[b] else s_lo[b]
            e_hi[b] = en if en > e_hi[b] else e_hi[b]
            e_lo[b] = en if en < e_lo[b] else e_lo[b]


@numba.njit(inline="always", **_LOOPS)
def _golden_pass(m, h, xy, tr, nb, nu, codes, par, E, q2, qs2, so, tau, value):
    """The summaries the criteria's values read (sigma_n max; its min for stress life; the
    range of E eps_n for SWT and strain life, of tau_e for the shear criteria: a straight
    path) and the values (:func:`_values`) of plane (ci, b) of every criterion ci and point b:
    ``q2``, ``qs2``, ``tau``, ``value`` (C, nb), ``so`` (6, C, nb) the rows of
    :func:`_grid_summaries`, indexed, not sliced (a view per criterion and iteration was an
    atomic reference count and its release); the same expressions, the same numbers."""
    a = 1.0 + nu
    for ci in range(codes.size):
        code = codes[ci]
        strain = code == SWT or code == STRAIN_LIFE
        if strain:
            for b in range(nb):
                so[0, ci, b], so[2, ci, b], so[3, ci, b] = -np.inf, -np.inf, np.inf
            for t in range(m.shape[0]):
                for b in range(nb):
                    c, s = q2[ci, b], qs2[ci, b]
                    ee = m[t, b] + h[t, b] * c + xy[t, b] * s
                    en = a * (m[t, b] + h[t, b] * c + xy[t, b] * s) - nu * tr[t, b]
                    so[0, ci, b] = max(so[0, ci, b], ee)
                    so[2, ci, b], so[3, ci, b] = max(so[2, ci, b], en), min(so[3, ci, b], en)
        elif _needs_shear(code):
            for b in range(nb):
                so[0, ci, b], so[4, ci, b], so[5, ci, b] = -np.inf, -np.inf, np.inf
            for t in range(m.shape[0]):
                for b in range(nb):
                    c, s = q2[ci, b], qs2[ci, b]
                    ee = m[t, b] + h[t, b] * c + xy[t, b] * s
                    te = xy[t, b] * c - h[t, b] * s
                    so[0, ci, b] = max(so[0, ci, b], ee)
                    so[4, ci, b], so[5, ci, b] = max(so[4, ci, b], te), min(so[5, ci, b], te)
        else:  # stress life: sigma_n's maximum and minimum (:func:`_extreme_normal`)
            for b in range(nb):
                so[0, ci, b], so[1, ci, b] = -np.inf, np.inf
            for t in range(m.shape[0]):
                for b in range(nb):
                    ee = m[t, b] + h[t, b] * q2[ci, b] + xy[t, b] * qs2[ci, b]
                    so[0, ci, b] = ee if ee > so[0, ci, b] else so[0, ci, b]
            for t in range(m.shape[0]):
                for b in range(nb):
                    ee = m[t, b] + h[t, b] * q2[ci, b] + xy[t, b] * qs2[ci, b]
                    so[1, ci, b] = ee if ee < so[1, ci, b] else so[1, ci, b]
        k, sy, shear_modulus, kind, limit = par[ci, 0], par[ci, 1], par[ci, 2], par[ci, 3], \
            par[ci, 4]  # fmt: skip
        if code == SWT:
            for b in range(nb):
                tau[ci, b] = 0.0
                value[ci, b] = so[0, ci, b] * (0.5 * (so[2, ci, b] - so[3, ci, b]) / E)
        elif code == STRAIN_LIFE:
            for b in range(nb):
                tau[ci, b] = 0.0
                value[ci, b] = 0.5 * (so[2, ci, b] - so[3, ci, b]) / E
        elif code == STRESS_LIFE:
            for b in range(nb):
                tau[ci, b] = 0.0
                s_hi, s_lo = so[0, ci, b], so[1, ci, b]
                amp, mean = 0.5 * (s_hi - s_lo), 0.5 * (s_hi + s_lo)
                if kind == NO_CORRECTION:
                    value[ci, b] = amp + 0.0 * mean
                    continue
                ratio = mean / limit
                factor = 1.0 - ratio * ratio if kind == GERBER else 1.0 - ratio
                value[ci, b] = amp / factor if factor > 0.0 else np.inf
        else:
            for b in range(nb):
                tau[ci, b] = 0.5 * (so[4, ci, b] - so[5, ci, b])
            if code == FINDLEY:
                for b in range(nb):
                    value[ci, b] = tau[ci, b] + k * so[0, ci, b]
            elif code == FATEMI_SOCIE:
                for b in range(nb):
                    value[ci, b] = (tau[ci, b] / shear_modulus) * (1.0 + k * so[0, ci, b] / sy)
            else:  # MWCM
                for b in range(nb):
                    value[ci, b] = tau[ci, b]


@numba.njit(**_JIT)
def _golden_in_plane(m, h, xy, tr, nb, codes, par, nu, E, step, levels, c2, s2, th, cres, ends,
                     gw, out):  # fmt: skip
    """The numpy search's ``_golden`` (in-plane) for a block of points, all criteria's planes
    of an iteration in one pass over the steps (the steps outside, the planes ``ci nb + b``,
    criterion ci and point b, inside: vectorised), the bracket's update by selects (its four
    cases as branches mispredict about one point in two).

    ``c2``, ``s2``, ``th`` (C nb): the grid's planes in, the critical ones out; ``cres``
    (5, C nb): their quantities, likewise; ``ends`` (2, C nb): the values of the grid
    neighbours, or empty (evaluated here). ``gw`` (12, C nb) scratch; ``out`` (12, C nb),
    the critical planes' summaries. An iteration
    evaluates only the summaries the criteria's values read, the others on the critical
    planes once at the end (the same numbers: the same planes, the same sums)."""
    n_c = codes.size
    n = n_c * nb
    lo, hi, f_lo, f_hi = gw[0, :n], gw[1, :n], gw[2, :n], gw[3, :n]
    cvalue, second, cscale, qx = gw[4, :n], gw[5, :n], gw[6, :n], gw[7, :n]
    ctau, camp = gw[10, :n], gw[11, :n]
    # the evaluated planes (cos, sin 2theta), their shear amplitudes, values and summaries:
    # indexed (ci, b) in :func:`_golden_pass`, rows of C nb in the update (views made once)
    ev = np.empty((10, n_c, nb))
    q2d, qs2d, tau2, val2, so = ev[0], ev[1], ev[2], ev[3], ev[4:]
    q2, qs2, tau, value = q2d.reshape(n), qs2d.reshape(n), tau2.reshape(n), val2.reshape(n)
    s_hi, e_hi, e_lo = so[0].reshape(n), so[2].reshape(n), so[3].reshape(n)
    for i in range(n):
        cvalue[i], second[i] = cres[0, i], cres[2, i]
        ctau[i], camp[i] = cres[1, i], cres[4, i]
        cscale[i] = max(abs(cvalue[i]), 1e-300)
        lo[i], hi[i] = -step, step
    if ends.shape[1]:  # the bracket's ends: the grid's neighbours (numpy evaluates them again)
        for i in range(n):
            f_lo[i], f_hi[i] = ends[0, i], ends[1, i]
    else:
        for j in range(2):
            tc, ts = _cos_sin(-2.0 * step if j == 0 else 2.0 * step)
            for i in range(n):
                q2[i], qs2[i] = c2[i] * tc - s2[i] * ts, s2[i] * tc + c2[i] * ts
            _golden_pass(m, h, xy, tr, nb, nu, codes, par, E, q2d, qs2d, so, tau2, val2)
            for i in range(n):
                if j == 0:
                    f_lo[i] = value[i]
                else:
                    f_hi[i] = value[i]
    # per plane: its criterion is MWCM, reads the strain; it moves at this iteration
    flags = np.empty((3, n), dtype=np.bool_)
    is_mwcm, is_strain, up = flags[0], flags[1], flags[2]
    for ci in range(n_c):
        code = codes[ci]
        for b in range(nb):
            is_mwcm[ci * nb + b] = code == MWCM
            is_strain[ci * nb + b] = code == SWT or code == STRAIN_LIFE
    for level in range(levels + 2):
        last = level == levels + 1
        if last:  # the vertex of the parabola through the ends and the current plane
            for i in range(n):
                a, b_ = cvalue[i] - f_hi[i], cvalue[i] - f_lo[i]
                den = -lo[i] * a + hi[i] * b_
                x = -0.5 * (lo[i] * lo[i] * a - hi[i] * hi[i] * b_) / den if den != 0.0 else 0.0
                qx[i] = x if math.isfinite(x) and lo[i] < x < hi[i] else 0.0
        else:
            for i in range(n):
                qx[i] = _GOLDEN * hi[i] if hi[i] > -lo[i] else _GOLDEN * lo[i]
        # the turned planes: the series by products, libm where the turn is long (rare: a
        # second loop), the plane itself where the offset is 0
        for i in range(n):
            d = 2.0 * qx[i]
            d2 = d * d
            tc = 1.0 + d2 * (_C0 + d2 * (_C1 + d2 * (_C2 + d2 * (_C3 + d2 * _C4))))
            ts = d + d * (d2 * (_S0 + d2 * (_S1 + d2 * (_S2 + d2 * (_S3 + d2 * _S4)))))
            q2[i], qs2[i] = c2[i] * tc - s2[i] * ts, s2[i] * tc + c2[i] * ts
        far = False  # a test of every plane first (vectorised), the branches only if needed
        for i in range(n):
            far = far | (abs(2.0 * qx[i]) >= 0.1)
        # conditional stores, here and below: a select of two arrays' elements became a load
        # through a selected pointer, which LLVM does not vectorise (the update took ~60 % of
        # this function, scalar); masked stores keep it vectorised, the same numbers
        for i in range(n):
            if qx[i] == 0.0:
                q2[i], qs2[i] = c2[i], s2[i]
        for i in range(n if far else 0):
            if abs(2.0 * qx[i]) >= 0.1:
                tc, ts = math.cos(2.0 * qx[i]), math.sin(2.0 * qx[i])
                q2[i], qs2[i] = c2[i] * tc - s2[i] * ts, s2[i] * tc + c2[i] * ts
        _golden_pass(m, h, xy, tr, nb, nu, codes, par, E, q2d, qs2d, so, tau2, val2)
        # the update, every criterion's planes in loops indexed from 0 (an index ci nb + b
        # may be negative for numba: gathers and scatters), each writing few arrays
        for i in range(n):
            v, cv = value[i], cvalue[i]
            tol = _TIE * cscale[i]
            tied = (v > cv + tol) | ((v >= cv - tol) & (s_hi[i] > second[i]))
            up[i] = tied if is_mwcm[i] else v > cv
        if not last:
            # r: the larger side is above. The end on the side of the turn takes the
            # current value where the plane moves (u), the new one where not: lo's where
            # u == r, hi's where u != r (every value loaded, then selected: vectorised)
            for i in range(n):
                x, u, v, cv = qx[i], up[i], value[i], cvalue[i]
                l0, h0, fl, fh = lo[i], hi[i], f_lo[i], f_hi[i]
                r = h0 > -l0
                nv = cv if u else v
                lo[i] = (-x if r else l0 - x) if u else (l0 if r else x)
                hi[i] = (h0 - x if r else -x) if u else (x if r else h0)
                f_lo[i] = nv if u == r else fl
                f_hi[i] = fh if u == r else nv
        for i in range(n):
            if up[i]:
                th[i] = th[i] + qx[i]
                c2[i], s2[i] = q2[i], qs2[i]
        for i in range(n):
            if up[i]:
                cvalue[i], second[i], ctau[i] = value[i], s_hi[i], tau[i]
        for i in range(n):
            if up[i] and is_strain[i]:  # read where the criterion's value is
                camp[i] = 0.5 * (e_hi[i] - e_lo[i]) / E
    # the critical planes' quantities: those of their winning iteration, sigma_n's minimum
    # and (where the value does not read it) the strain's range once on the final planes
    for ci in range(n_c):
        code, start = codes[ci], ci * nb
        if code == SWT or code == STRAIN_LIFE:
            _extreme_normal(m, h, xy, nb, c2, s2, start, out[1], False)
            continue
        _final_extremes(m, h, xy, tr, nb, nu, c2, s2, start, out)
        e_hi, e_lo, amp = out[2, start : start + nb], out[3, start : start + nb], \
            camp[start : start + nb]  # fmt: skip
        for b in range(nb):
            amp[b] = 0.5 * (e_hi[b] - e_lo[b]) / E
    for i in range(n):
        cres[0, i], cres[1, i], cres[2, i] = cvalue[i], ctau[i], second[i]
        cres[3, i], cres[4, i] = out[1, i], camp[i]


@numba.njit(**_JIT)
def search(
    stress, grid, axes, rank, grid_theta, grid_psi, codes, par, nu, E, steps, levels, in_plane
):
    """Critical planes and their quantities of every criterion at every point.

    ``stress`` (T, P, 4); ``grid`` (4, G): cos 2theta, sin 2theta, sin psi, cos psi of the
    coarse planes at angles ``grid_theta``, ``grid_psi``, in 3D ordered as ``axes`` says
    (:func:`_grid_summaries`), ``rank`` their places in the numpy search's grid; ``codes``
    (C,) criterion codes, ``par`` (C, 5) their constants. Returns theta, psi (C, P) and
    (5, C, P): value, shear amplitude, sigma_n max, sigma_n min, normal strain amplitude on
    the critical planes.
    """
    n_t, n_p = stress.shape[0], stress.shape[1]
    n_c = codes.size
    n_g = grid.shape[1]
    k = 2 if in_plane else 4
    theta_out = np.empty((n_c, n_p))
    psi_out = np.empty((n_c, n_p))
    res_out = np.empty((5, n_c, n_p))
    nb_max = min(BLOCK, n_p)
    # rows of one array each, padded so that rows do not start a multiple of 4 KiB apart
    # (the loops stream many rows at once: rows that share L1 sets evict each other)
    steps_rows = np.empty((7, n_t * nb_max + _PAD))
    data = (
        steps_rows[0, : n_t * nb_max].reshape((n_t, nb_max)),
        steps_rows[1, : n_t * nb_max].reshape((n_t, nb_max)),
        steps_rows[2, : n_t * nb_max].reshape((n_t, nb_max)),
        steps_rows[3, : n_t * nb_max].reshape((n_t, nb_max)),
        steps_rows[4, : n_t * nb_max].reshape((n_t, nb_max)),
        steps_rows[5, :n_t],
        steps_rows[6, :n_t],
    )
    m, h, xy, zz, tr = data[0], data[1], data[2], data[3], data[4]
    size = max(n_g, n_c * k * nb_max)
    rows = np.empty((18, size + _PAD))
    work = (
        rows[:12],
        rows[12, :size],
        rows[13, :size],
        rows[14, :size],
        rows[15, :size],
        rows[16, :size],
        rows[17, :size],
        np.empty(size, dtype=np.bool_),
        np.empty(size, dtype=np.int64),
    )
    n_cur = n_c * nb_max
    cur_rows = np.empty((8, n_cur + _PAD))
    cur_planes = (
        cur_rows[0, :n_cur],
        cur_rows[1, :n_cur],
        cur_rows[2, :n_cur],
        cur_rows[3, :n_cur],
        np.full((n_cur, 3), -1, dtype=np.int64),
    )
    cur_angles = (cur_rows[4, :n_cur], cur_rows[5, :n_cur])
    cur = (cur_rows[6, :n_cur], cur_rows[7, :n_cur], cur_planes[4])
    n_q = n_c * k * nb_max
    cand_rows = np.empty((6, n_q + _PAD))
    cand = (
        cand_rows[0, :n_q],
        cand_rows[1, :n_q],
        cand_rows[2, :n_q],
        cand_rows[3, :n_q],
        np.full((n_q, 3), -1, dtype=np.int64),
    )
    cand_angles = (cand_rows[4, :n_q], cand_rows[5, :n_q])
    exact = np.empty(n_q, dtype=np.bool_)  # the refinement's planes whose tau is exact
    bracket = np.empty((12, n_cur + _PAD))  # the golden search's scratch
    ends = np.empty((2, n_cur + _PAD))
    # the in-plane grid closes on itself (180 degrees a whole number of steps): the grid's
    # neighbours of a plane are its bracket's ends, their values known
    wraps = in_plane and abs(n_g * steps[0] - np.pi) < 1e-9
    # the 3D grid's summaries in single precision (:func:`_grid_summaries`)
    axes32 = (axes[0].astype(np.float32), axes[1].astype(np.float32),
              axes[2].astype(np.float32), axes[3].astype(np.float32))  # fmt: skip
    scratch = (
        np.empty((6, axes[0].size + _PAD), dtype=np.float32),
        np.empty((12, n_g + _PAD), dtype=np.float32),
    )
    best_block = np.empty(n_cur, dtype=np.int64)
    found_block = np.empty((7, n_cur))
    cres = np.empty((5, n_cur + _PAD))
    sup = np.empty(3, dtype=np.int64)
    taus = np.empty((8, nb_max + _PAD))  # :func:`_plane_taus`' scratch
    c2, s2, sp, cp, _ = cur_planes
    th, ps = cur_angles
    for p0 in range(0, n_p, nb_max):
        nb = min(nb_max, n_p - p0)
        # the block's points as a view indexed from 0 (an index p0 + b numba cannot prove
        # non-negative is wrapped around, a select in every load; so are the outputs below)
        block = stress[:, p0 : p0 + nb]
        for t in range(n_t):
            for b in range(nb):
                sxx, syy = block[t, b, 0], block[t, b, 1]
                m[t, b] = 0.5 * (sxx + syy)
                h[t, b] = 0.5 * (sxx - syy)
                xy[t, b] = block[t, b, 2]
                zz[t, b] = block[t, b, 3]
                tr[t, b] = 2.0 * m[t, b] + zz[t, b]
        if in_plane:  # the block's points in one call (:func:`_coarse_in_plane`)
            _coarse_in_plane(m, h, xy, tr, 0, nb, nu, grid[0], grid[1], codes, par, E,
                             best_block, found_block)  # fmt: skip
            for i in range(n_c * nb):
                g = best_block[i]
                for r in range(5):
                    cres[r, i] = found_block[r, i]
                ends[0, i], ends[1, i] = found_block[5, i], found_block[6, i]
                th[i], ps[i] = grid_theta[g], grid_psi[g]
                c2[i], s2[i], sp[i], cp[i] = grid[0, g], grid[1, g], grid[2, g], grid[3, g]
        else:  # the block's points in one call (:func:`_coarse_3d`)
            _coarse_3d(data, nb, grid, axes32, rank, codes, par, nu, E, work, scratch,
                       best_block, found_block, sup)  # fmt: skip
            for i in range(n_c * nb):
                g = best_block[i]
                for r in range(5):
                    cres[r, i] = found_block[r, i]
                th[i], ps[i] = grid_theta[g], grid_psi[g]
                c2[i], s2[i], sp[i], cp[i] = grid[0, g], grid[1, g], grid[2, g], grid[3, g]
        if not in_plane:
            # the grid's 3D planes were chosen in single precision: their quantities again in
            # double (the numpy search evaluates its start planes so too)
            for i in range(n_c * nb):
                cur_planes[4][i, 0] = -1
            _evaluate(data, nb, cur_planes, n_c, 1, codes, par, nu, E, False, cur, work, exact)
            for i in range(n_c * nb):
                _keep(cres, i, work[4], work[3], work[0], i, E)
        if in_plane:
            _golden_in_plane(m, h, xy, tr, nb, codes, par, nu, E, steps[0], levels, c2, s2, th,
                             cres, ends if wraps else ends[:, :0], bracket, work[0])  # fmt: skip
        else:
            _refine_block(data, nb, cur_planes, cur_angles, cur, cres, cand, cand_angles,
                          codes, par, nu, E, steps, levels, work, exact)  # fmt: skip
        # a criterion whose search needs no shear reports its plane's exact shear amplitude
        for ci in range(n_c):
            if _needs_shear(codes[ci]):
                continue
            a, z = ci * nb, (ci + 1) * nb
            _plane_taus(m, h, xy, zz, nb, c2[a:z], s2[a:z], sp[a:z], cp[a:z], cres[1, a:z],
                        data[5], data[6], sup, taus)  # fmt: skip
        for ci in range(n_c):
            theta_c, psi_c = theta_out[ci, p0 : p0 + nb], psi_out[ci, p0 : p0 + nb]
            for b in range(nb):
                theta_c[b] = th[ci * nb + b]
                psi_c[b] = ps[ci * nb + b]
            for r in range(5):
                res_c = res_out[r, ci, p0 : p0 + nb]
                for b in range(nb):
                    res_c[b] = cres[r, ci * nb + b]
    return theta_out, psi_out, res_out


#: the rows of :func:`report`, the fields of a ``CriterionResult`` in its order
REPORT_ROWS = (
    "value",
    "normal_angle_deg",
    "normal_tilt_deg",
    "shear_stress_amplitude",
    "normal_stress_max",
    "normal_stress_amplitude",
    "normal_stress_mean",
    "normal_strain_amplitude",
    "shear_strain_amplitude",
)


@numba.njit(**_JIT)  # no contraction: numpy's arithmetic, operation by operation
def report(theta, psi, res, shear_modulus):
    """The reported quantities (9, C, P) of :data:`REPORT_ROWS` from :func:`search`'s theta,
    psi and ``res``: numpy's ``rad2deg(mod(theta, pi))``, ``90 - rad2deg(psi)``, the stress
    amplitude and mean and tau / G, the same numbers in one pass (numpy's ~40 operations on
    the points' arrays took ~0.5 ms of a 10 ms in-plane search: ``np.mod`` alone 65 us)."""
    n_c, n_p = theta.shape
    out = np.empty((9, n_c, n_p))
    deg = 180.0 / np.pi
    for ci in range(n_c):
        for p in range(n_p):
            mod = np.mod(theta[ci, p], np.pi)  # numba's is numpy's npy_divmod
            smax, smin, tau = res[2, ci, p], res[3, ci, p], res[1, ci, p]
            out[0, ci, p] = res[0, ci, p]
            out[1, ci, p] = mod * deg
            out[2, ci, p] = 90.0 - psi[ci, p] * deg
            out[3, ci, p] = tau
            out[4, ci, p] = smax
            out[5, ci, p] = 0.5 * (smax - smin)
            out[6, ci, p] = 0.5 * (smax + smin)
            out[7, ci, p] = res[4, ci, p]
            out[8, ci, p] = tau / shear_modulus
    return out
