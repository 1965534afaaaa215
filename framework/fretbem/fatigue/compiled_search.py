"""Compiled (numba) critical-plane search: every criterion's planes, point by point, in one loop.

The numpy search (:mod:`.critical_plane`) projects the stresses of every (step, point, plane)
into arrays and reduces them; here one loop per point computes each plane's normal and shear
stresses step by step and keeps only their running maxima and minima, for all criteria at
once, so the (step, point, plane) array never exists. The algorithm is the numpy search's,
decision for decision: the coarse grid (in double precision here, float32 there), the exact
minimum circumscribed circle only where its bounds leave a plane's rank open, the pattern
search with halving steps that evaluates every criterion's candidates together, the parabolic
step and the final evaluation. Neighbouring planes are reached by rotating the cosines and
sines of the current plane (no trigonometric call per candidate).

Functions are compiled on first use and cached on disk (``cache=True``), so a fresh process
pays numba's import and the cache load. Importing this module imports numba:
:mod:`.critical_plane` imports it only when the search is large enough to repay it, or when
numba is loaded already.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_JIT = {"cache": True, "nogil": True, "error_model": "numpy"}

#: criterion codes (the order of :data:`fretbem.fatigue.critical_plane.METHODS`)
SWT, FINDLEY, FATEMI_SOCIE, MWCM, STRESS_LIFE, STRAIN_LIFE = range(6)
#: mean-stress correction kinds of stress_life: none, 1 - m/L (Goodman, Morrow), 1 - (m/L)^2
NO_CORRECTION, LINEAR, GERBER = range(3)
#: rows of the per-plane summaries: sigma_n, E eps_n, then the shear extents
_SN_MAX, _SN_MIN, _EN_MAX, _EN_MIN = range(4)
#: in-plane: tau_e; 3D: tau_1, tau_2, tau_1 + tau_2, tau_1 - tau_2
_SHEAR = 4

_HALF_SQRT2 = 0.5 * math.sqrt(2.0)
_INSIDE = 1e-10  # as mcc.INSIDE_TOLERANCE
_TIE = 1e-10  # as critical_plane.MWCM_TIE_TOLERANCE


@numba.njit(**_JIT)
def _summaries(mean, half, sxy, szz, trace, nu, c2, s2, sp, cp, n, in_plane, out):
    """Running max / min over the steps of every plane's quantities into ``out`` (12, n)."""
    n_t = mean.size
    a = 1.0 + nu
    for g in range(n):
        for r in range(0, 12, 2):
            out[r, g] = -np.inf
            out[r + 1, g] = np.inf
    for t in range(n_t):
        m, h, xy, zz, tr = mean[t], half[t], sxy[t], szz[t], nu * trace[t]
        if in_plane:
            for g in range(n):
                ee = m + h * c2[g] + xy * s2[g]
                te = xy * c2[g] - h * s2[g]
                en = a * ee - tr
                out[0, g] = max(out[0, g], ee)
                out[1, g] = min(out[1, g], ee)
                out[2, g] = max(out[2, g], en)
                out[3, g] = min(out[3, g], en)
                out[4, g] = max(out[4, g], te)
                out[5, g] = min(out[5, g], te)
        else:
            for g in range(n):
                ee = m + h * c2[g] + xy * s2[g]
                te = xy * c2[g] - h * s2[g]
                sn = (sp[g] * sp[g]) * ee + (cp[g] * cp[g]) * zz
                en = a * sn - tr
                px = (sp[g] * cp[g]) * (ee - zz)
                py = sp[g] * te
                u, v = px + py, px - py
                out[0, g] = max(out[0, g], sn)
                out[1, g] = min(out[1, g], sn)
                out[2, g] = max(out[2, g], en)
                out[3, g] = min(out[3, g], en)
                out[4, g] = max(out[4, g], px)
                out[5, g] = min(out[5, g], px)
                out[6, g] = max(out[6, g], py)
                out[7, g] = min(out[7, g], py)
                out[8, g] = max(out[8, g], u)
                out[9, g] = min(out[9, g], u)
                out[10, g] = max(out[10, g], v)
                out[11, g] = min(out[11, g], v)


@numba.njit(**_JIT)
def _bounds(out, g):
    """Lower and upper bounds of the circumscribed radius of plane ``g``'s shear path."""
    rx = out[4, g] - out[5, g]
    ry = out[6, g] - out[7, g]
    ru = (out[8, g] - out[9, g]) * _HALF_SQRT2
    rv = (out[10, g] - out[11, g]) * _HALF_SQRT2
    lower = 0.5 * max(max(rx, ry), max(ru, rv))
    upper = 0.5 * math.sqrt(min(rx * rx + ry * ry, ru * ru + rv * rv))
    return lower, upper


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
def _circle(x, y):
    """Radius of the smallest circle enclosing the points ``x``, ``y``: the support-set
    iteration of :func:`fretbem.fatigue.mcc.minimum_circumscribed_circle_xy`, one set."""
    m = x.size
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
    cx, cy = 0.5 * (x[a] + x[b]), 0.5 * (y[a] + y[b])
    radius = 0.5 * math.sqrt(best)
    sx = np.array([x[a], x[b], x[b]])
    sy = np.array([y[a], y[b], y[b]])
    ax = np.empty(4)
    ay = np.empty(4)
    for _ in range(200):
        far, dmax = 0, -1.0
        for i in range(m):
            d = (x[i] - cx) ** 2 + (y[i] - cy) ** 2
            if d > dmax:
                far, dmax = i, d
        if not math.sqrt(dmax) > radius * (1.0 + _INSIDE) + 1e-300:
            return radius
        qx, qy = x[far], y[far]
        ax[:3], ay[:3] = sx, sy
        ax[3], ay[3] = qx, qy
        pick, pcx, pcy, pr = -1, 0.0, 0.0, np.inf
        for c in range(6):  # the candidates of mcc._smallest_with, in its order
            if c < 3:
                ccx, ccy = 0.5 * (sx[c] + qx), 0.5 * (sy[c] + qy)
                cr = 0.5 * math.hypot(sx[c] - qx, sy[c] - qy)
            else:
                i, j = (0, 1) if c == 3 else ((0, 2) if c == 4 else (1, 2))
                ccx, ccy, cr = _circumcircle(sx[i], sy[i], sx[j], sy[j], qx, qy)
            if not math.isfinite(cr):
                continue
            slack = _INSIDE * cr + 1e-300
            inside = True
            for k in range(4):
                if math.hypot(ax[k] - ccx, ay[k] - ccy) > cr + slack:
                    inside = False
                    break
            if inside and cr < pr:
                pick, pcx, pcy, pr = c, ccx, ccy, cr
        i, j = (
            (pick, pick)
            if pick < 3
            else ((0, 1) if pick == 3 else ((0, 2) if pick == 4 else (1, 2)))
        )
        nx0, ny0, nx1, ny1 = sx[i], sy[i], sx[j], sy[j]
        sx[0], sy[0], sx[1], sy[1], sx[2], sy[2] = nx0, ny0, nx1, ny1, qx, qy
        cx, cy, radius = pcx, pcy, pr
    return radius


@numba.njit(**_JIT)
def _exact_tau(mean, half, sxy, szz, c2, s2, sp, cp, x, y):
    """The exact shear amplitude of one plane: its path over the steps and its circle."""
    for t in range(mean.size):
        ee = mean[t] + half[t] * c2 + sxy[t] * s2
        te = sxy[t] * c2 - half[t] * s2
        x[t] = (sp * cp) * (ee - szz[t])
        y[t] = sp * te
    return _circle(x, y)


@numba.njit(**_JIT)
def _value(code, smax, smin, ea, tau, par):
    """The parameter of criterion ``code`` (``par``: k, yield, G, correction kind, limit)."""
    if code == SWT:
        return smax * ea
    if code == STRAIN_LIFE:
        return ea
    if code == STRESS_LIFE:
        amp, mean = 0.5 * (smax - smin), 0.5 * (smax + smin)
        kind = par[3]
        if kind == NO_CORRECTION:
            return amp + 0.0 * mean
        ratio = mean / par[4]
        factor = 1.0 - ratio * ratio if kind == GERBER else 1.0 - ratio
        return amp / factor if factor > 0.0 else np.inf
    if code == FINDLEY:
        return tau + par[0] * smax
    if code == FATEMI_SOCIE:
        return (tau / par[2]) * (1.0 + par[0] * smax / par[1])
    return tau  # MWCM


@numba.njit(**_JIT)
def _better(code, new, new2, old, old2, scale):
    if code != MWCM:
        return new > old
    tol = _TIE * scale
    return (new > old + tol) or ((new >= old - tol) and (new2 > old2))


@numba.njit(**_JIT)
def _needs_shear(code):
    return code == FINDLEY or code == FATEMI_SOCIE or code == MWCM


@numba.njit(**_JIT)
def _evaluate(
    point, c2, s2, sp, cp, n, per, codes, par, nu, E, in_plane, against, current, scale, res
):
    """Plane quantities and parameter values of ``n`` planes, ``per`` per criterion in order.

    ``res`` (5, n): value, tau, sigma_n max, sigma_n min, normal strain amplitude. With
    ``against``, a plane whose value cannot beat its criterion's ``current`` keeps the lower
    bound of its shear amplitude (as the numpy search's ``_SharedPass._exact``).
    """
    mean, half, sxy, szz, trace, out, x, y = point
    _summaries(mean, half, sxy, szz, trace, nu, c2, s2, sp, cp, n, in_plane, out)
    for g in range(n):
        ci = g // per
        code = codes[ci]
        smax, smin = out[0, g], out[1, g]
        ea = 0.5 * (out[2, g] - out[3, g]) / E
        tau = 0.0
        if _needs_shear(code):
            if in_plane:
                tau = 0.5 * (out[4, g] - out[5, g])
            else:
                lo, hi = _bounds(out, g)
                tau = lo
                if hi > lo * (1.0 + 1e-12):
                    need = True
                    if against:
                        top = max(
                            _value(code, smax, smin, ea, lo, par[ci]),
                            _value(code, smax, smin, ea, hi, par[ci]),
                        )
                        slack = _TIE * scale[ci] if code == MWCM else 0.0
                        need = top >= current[ci] - slack
                    if need:
                        tau = _exact_tau(mean, half, sxy, szz, c2[g], s2[g], sp[g], cp[g], x, y)
        res[0, g] = _value(code, smax, smin, ea, tau, par[ci])
        res[1, g] = tau
        res[2, g] = smax
        res[3, g] = smin
        res[4, g] = ea


@numba.njit(**_JIT)
def _coarse(point, grid, codes, par, nu, E, in_plane, tau, best):
    """Index of the best grid plane of every criterion into ``best`` (as numpy's _coarse)."""
    mean, half, sxy, szz, trace, out, x, y = point
    c2, s2, sp, cp = grid[0], grid[1], grid[2], grid[3]
    n_g = c2.size
    _summaries(mean, half, sxy, szz, trace, nu, c2, s2, sp, cp, n_g, in_plane, out)
    any_shear = False
    for code in codes:
        any_shear = any_shear or _needs_shear(code)
    for g in range(n_g):
        tau[g] = 0.0
        if any_shear and in_plane:
            tau[g] = 0.5 * (out[4, g] - out[5, g])
    if any_shear and not in_plane:
        # the exact circle only on planes whose upper bound reaches the best lower bound
        need = np.zeros(n_g, dtype=np.bool_)
        hi_tau = np.empty(n_g)
        for g in range(n_g):
            tau[g], hi_tau[g] = _bounds(out, g)
        for ci in range(codes.size):
            code = codes[ci]
            if not _needs_shear(code):
                continue
            best_lo = -np.inf
            for g in range(n_g):
                ea = 0.5 * (out[2, g] - out[3, g]) / E
                a = _value(code, out[0, g], out[1, g], ea, tau[g], par[ci])
                b = _value(code, out[0, g], out[1, g], ea, hi_tau[g], par[ci])
                best_lo = max(best_lo, min(a, b))
            slack = _TIE * abs(best_lo) if code == MWCM else 0.0
            for g in range(n_g):
                ea = 0.5 * (out[2, g] - out[3, g]) / E
                a = _value(code, out[0, g], out[1, g], ea, tau[g], par[ci])
                b = _value(code, out[0, g], out[1, g], ea, hi_tau[g], par[ci])
                if max(a, b) >= best_lo - slack:
                    need[g] = True
        for g in range(n_g):
            if need[g] and hi_tau[g] > tau[g] * (1.0 + 1e-12):
                tau[g] = _exact_tau(mean, half, sxy, szz, c2[g], s2[g], sp[g], cp[g], x, y)
    for ci in range(codes.size):
        code = codes[ci]
        top, arg, arg2 = -np.inf, 0, 0
        first = True
        for g in range(n_g):
            ea = 0.5 * (out[2, g] - out[3, g]) / E
            t = tau[g] if _needs_shear(code) else 0.0
            v = _value(code, out[0, g], out[1, g], ea, t, par[ci])
            if first or v > top:
                top, arg, first = v, g, False
        if code == MWCM:  # ties within the tolerance: the largest normal stress
            tol = _TIE * max(abs(top), 1e-300)
            second = -np.inf
            arg2 = -1
            for g in range(n_g):
                if tau[g] >= top - tol and (arg2 < 0 or out[0, g] > second):
                    second, arg2 = out[0, g], g
            arg = arg2
        best[ci] = arg


@numba.njit(**_JIT)
def _argbest(code, res, start, count):
    """Index (from ``start``) of the best of ``count`` candidates of one criterion."""
    arg = start
    for g in range(start + 1, start + count):
        if res[0, g] > res[0, arg]:
            arg = g
    if code == MWCM:
        top = res[0, arg]
        tol = _TIE * max(abs(top), 1e-300)
        arg2 = -1
        for g in range(start, start + count):
            if res[0, g] >= top - tol and (arg2 < 0 or res[2, g] > res[2, arg2]):
                arg2 = g
        arg = arg2
    return arg


@numba.njit(**_JIT)
def _shifted(c2, s2, sp, cp, psi, dp, cos2t, sin2t, cosp, sinp):
    """cos 2theta, sin 2theta, sin psi, cos psi, psi of the plane moved by (dt, dp); psi is
    clipped to [0, pi/2] as the numpy search clips it."""
    nc2 = c2 * cos2t - s2 * sin2t
    ns2 = s2 * cos2t + c2 * sin2t
    npsi = psi + dp
    if dp == 0.0:
        return nc2, ns2, sp, cp, psi
    if npsi >= 0.5 * np.pi:
        return nc2, ns2, 1.0, math.cos(0.5 * np.pi), 0.5 * np.pi
    if npsi <= 0.0:
        return nc2, ns2, 0.0, 1.0, 0.0
    return nc2, ns2, sp * cosp + cp * sinp, cp * cosp - sp * sinp, npsi


@numba.njit(**_JIT)
def _parabola(res, lo, centre, h):
    """The step to the vertex of the parabola through res[0, lo], centre, res[0, lo + 1] at
    -h, 0, h; none where it opens upwards, at most h (the numpy search's nan_to_num, clip)."""
    curv = res[0, lo] - 2.0 * centre + res[0, lo + 1]
    d = 0.0
    if curv < 0:
        d = 0.5 * h * (res[0, lo] - res[0, lo + 1]) / curv
    if math.isnan(d):
        d = 0.0
    return min(max(d, -h), h)


@numba.njit(**_JIT)
def search(stress, grid, grid_theta, grid_psi, codes, par, nu, E, steps, levels, in_plane):
    """Critical planes and their quantities of every criterion at every point.

    ``stress`` (T, P, 4); ``grid`` (4, G): cos 2theta, sin 2theta, sin psi, cos psi of the
    coarse planes at angles ``grid_theta``, ``grid_psi``; ``codes`` (C,) criterion codes,
    ``par`` (C, 5) their constants. Returns theta, psi (C, P) and (5, C, P): value, shear
    amplitude, sigma_n max, sigma_n min, normal strain amplitude on the critical planes.
    """
    n_t, n_p = stress.shape[0], stress.shape[1]
    n_c = codes.size
    n_g = grid.shape[1]
    k = 2 if in_plane else 4
    theta_out = np.empty((n_c, n_p))
    psi_out = np.empty((n_c, n_p))
    res_out = np.empty((5, n_c, n_p))
    mean, half = np.empty(n_t), np.empty(n_t)
    sxy, szz, trace = np.empty(n_t), np.empty(n_t), np.empty(n_t)
    out = np.empty((12, max(n_g, n_c * k)))
    x, y = np.empty(n_t), np.empty(n_t)
    point = (mean, half, sxy, szz, trace, out, x, y)
    tau_g = np.empty(n_g)
    best = np.empty(n_c, dtype=np.int64)
    # the current plane of each criterion, and its value
    th, ps = np.empty(n_c), np.empty(n_c)
    c2, s2, sp, cp = np.empty(n_c), np.empty(n_c), np.empty(n_c), np.empty(n_c)
    value, second, scale = np.empty(n_c), np.empty(n_c), np.empty(n_c)
    res = np.empty((5, n_c * k))
    one = np.empty((5, n_c))
    cc2, cs2, csp, ccp = np.empty(n_c * k), np.empty(n_c * k), np.empty(n_c * k), np.empty(n_c * k)
    cth, cps = np.empty(n_c * k), np.empty(n_c * k)
    # rotations of every level (and of the parabolic step's level)
    rot = np.empty((levels + 1, 6))
    for level in range(levels + 1):
        ht = steps[0] / 2 ** (level + 1) if level < levels else steps[0] / 2**levels
        hp = steps[1] / 2 ** (level + 1) if level < levels else steps[1] / 2**levels
        rot[level] = ht, hp, math.cos(2 * ht), math.sin(2 * ht), math.cos(hp), math.sin(hp)
    dt = np.empty(k)
    dp = np.empty(k)
    for p in range(n_p):
        for t in range(n_t):
            sxx_, syy_, sxy_, szz_ = (
                stress[t, p, 0],
                stress[t, p, 1],
                stress[t, p, 2],
                stress[t, p, 3],
            )
            mean[t] = 0.5 * (sxx_ + syy_)
            half[t] = 0.5 * (sxx_ - syy_)
            sxy[t] = sxy_
            szz[t] = szz_
            trace[t] = 2.0 * mean[t] + szz_
        _coarse(point, grid, codes, par, nu, E, in_plane, tau_g, best)
        for ci in range(n_c):
            g = best[ci]
            th[ci], ps[ci] = grid_theta[g], grid_psi[g]
            c2[ci], s2[ci], sp[ci], cp[ci] = grid[0, g], grid[1, g], grid[2, g], grid[3, g]
        _evaluate(point, c2, s2, sp, cp, n_c, 1, codes, par, nu, E, in_plane, False, value,
                  scale, one)  # fmt: skip
        for ci in range(n_c):
            value[ci] = one[0, ci]
            second[ci] = one[2, ci]
            scale[ci] = max(abs(value[ci]), 1e-300)
        for level in range(levels + 1):
            ht, hp, cos2t, sin2t, cosp, sinp = rot[level]
            dt[0], dt[1] = -ht, ht
            dp[0], dp[1] = 0.0, 0.0
            if not in_plane:
                dt[2], dt[3] = 0.0, 0.0
                dp[2], dp[3] = -hp, hp
            for ci in range(n_c):
                for j in range(k):
                    g = ci * k + j
                    sign = 1.0 if (dt[j] > 0 or dp[j] > 0) else -1.0
                    r2t = cos2t if dt[j] != 0 else 1.0
                    s2t = sign * sin2t if dt[j] != 0 else 0.0
                    rp = cosp if dp[j] != 0 else 1.0
                    sq = sign * sinp if dp[j] != 0 else 0.0
                    cc2[g], cs2[g], csp[g], ccp[g], cps[g] = _shifted(
                        c2[ci], s2[ci], sp[ci], cp[ci], ps[ci], dp[j], r2t, s2t, rp, sq
                    )
                    cth[g] = th[ci] + dt[j]
            last = level == levels
            _evaluate(point, cc2, cs2, csp, ccp, n_c * k, k, codes, par, nu, E, in_plane,
                      not last, value, scale, res)  # fmt: skip
            if not last:
                for ci in range(n_c):
                    j = _argbest(codes[ci], res, ci * k, k)
                    if _better(codes[ci], res[0, j], res[2, j], value[ci], second[ci], scale[ci]):
                        th[ci], ps[ci] = cth[j], cps[j]
                        c2[ci], s2[ci], sp[ci], cp[ci] = cc2[j], cs2[j], csp[j], ccp[j]
                        value[ci], second[ci] = res[0, j], res[2, j]
                continue
            # one parabolic step per angle through the last level's three values
            for ci in range(n_c):
                shift_t = _parabola(res, ci * k, value[ci], ht)
                nth = th[ci] + shift_t
                nps = ps[ci]
                if not in_plane:
                    shift_p = _parabola(res, ci * k + 2, value[ci], hp)
                    nps = min(max(ps[ci] + shift_p, 0.0), 0.5 * np.pi)
                r2t, s2t = math.cos(2 * shift_t), math.sin(2 * shift_t)
                cc2[ci] = c2[ci] * r2t - s2[ci] * s2t
                cs2[ci] = s2[ci] * r2t + c2[ci] * s2t
                if nps == ps[ci]:
                    csp[ci], ccp[ci] = sp[ci], cp[ci]
                elif nps == 0.5 * np.pi:
                    csp[ci], ccp[ci] = 1.0, math.cos(0.5 * np.pi)
                elif nps == 0.0:
                    csp[ci], ccp[ci] = 0.0, 1.0
                else:
                    dq = nps - ps[ci]
                    csp[ci] = sp[ci] * math.cos(dq) + cp[ci] * math.sin(dq)
                    ccp[ci] = cp[ci] * math.cos(dq) - sp[ci] * math.sin(dq)
                cth[ci], cps[ci] = nth, nps
            _evaluate(point, cc2, cs2, csp, ccp, n_c, 1, codes, par, nu, E, in_plane, True,
                      value, scale, one)  # fmt: skip
            for ci in range(n_c):
                if _better(codes[ci], one[0, ci], one[2, ci], value[ci], second[ci], scale[ci]):
                    th[ci], ps[ci] = cth[ci], cps[ci]
                    c2[ci], s2[ci], sp[ci], cp[ci] = cc2[ci], cs2[ci], csp[ci], ccp[ci]
        _evaluate(point, c2, s2, sp, cp, n_c, 1, codes, par, nu, E, in_plane, False, value,
                  scale, one)  # fmt: skip
        for ci in range(n_c):
            theta_out[ci, p] = th[ci]
            psi_out[ci, p] = ps[ci]
            for r in range(5):
                res_out[r, ci, p] = one[r, ci]
    return theta_out, psi_out, res_out
