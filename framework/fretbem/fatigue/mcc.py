"""Minimum circumscribed circle of many small 2D point sets at once (shear amplitude on a plane).

The shear stress vector on a material plane traces a path over the cycle; its amplitude under
non-proportional loading is the radius of the smallest circle that encloses the path
(Papadopoulos et al., "A comparative study of multiaxial high-cycle fatigue criteria for
metals", Int. J. Fatigue 19 (1997) 219-235). Half the longest chord is only a lower bound.

The algorithm is the support-set iteration of Elzinga and Hearn ("Geometrical solutions for
some minimax location problems", Transportation Science 6 (1972) 379-394): keep the circle
of at most three support points; while a point lies outside, replace the circle by the smallest
circle of the support points plus that farthest point (which lies on its boundary). The radius
grows strictly, so the loop ends with the exact circle; all sets advance in lockstep, and the
sets that are done drop out of the arrays.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "circle_bounds",
    "circle_bounds_xy",
    "minimum_circumscribed_circle",
    "minimum_circumscribed_circle_xy",
]

#: relative slack on "inside the circle" (round-off of the circle through three points)
INSIDE_TOLERANCE = 1e-10
#: 1 / sqrt(2): projections on the diagonals
_HALF_SQRT2 = 0.5 * np.sqrt(2.0)
#: the iteration ends after this many rounds; each round enlarges the radius strictly
MAX_ROUNDS = 200
#: a point counts as on the circle within this fraction of its column's coordinate size too
#: (the round-off of the distances; a circle of radius 1e-9 among stresses of 30 MPa)
ROUNDING = 1e-13


def _initial_circle(x: np.ndarray, y: np.ndarray):
    """Diametral circle of an approximate farthest pair: a lower bound on the radius.

    ``x``, ``y`` (m, K): the m path points of K sets, one set per column.
    """
    d0 = (x - x[:1]) ** 2 + (y - y[:1]) ** 2
    a = np.argmax(d0, axis=0)[None]
    ax = np.take_along_axis(x, a, axis=0)[0]
    ay = np.take_along_axis(y, a, axis=0)[0]
    da = (x - ax) ** 2 + (y - ay) ** 2
    b = np.argmax(da, axis=0)[None]
    bx = np.take_along_axis(x, b, axis=0)[0]
    by = np.take_along_axis(y, b, axis=0)[0]
    radius = 0.5 * np.sqrt(np.take_along_axis(da, b, axis=0)[0])
    return 0.5 * (ax + bx), 0.5 * (ay + by), radius, (ax, ay), (bx, by)


def circle_bounds_xy(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds on the circumscribed radius of sets given as columns (m, K).

    From the extents of each set along four directions (x, y and the diagonals): half the
    largest extent is a lower bound, and the half-diagonal of the smallest of the two bounding
    boxes (axis-aligned, diagonal-aligned) an upper bound. For a straight-line path they are
    within 8 % of each other; only reductions over the path, so cheap.
    """
    rx = x.max(axis=0) - x.min(axis=0)
    ry = y.max(axis=0) - y.min(axis=0)
    u = x + y
    v = x - y
    ru = (u.max(axis=0) - u.min(axis=0)) * _HALF_SQRT2
    rv = (v.max(axis=0) - v.min(axis=0)) * _HALF_SQRT2
    lower = 0.5 * np.maximum(np.maximum(rx, ry), np.maximum(ru, rv))
    upper = 0.5 * np.sqrt(np.minimum(rx * rx + ry * ry, ru * ru + rv * rv))
    return lower, upper


def circle_bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds on the circumscribed radius of each set ``points`` (K, m, 2)."""
    points = np.asarray(points, dtype=float)
    return circle_bounds_xy(points[:, :, 0].T, points[:, :, 1].T)


def _circumcircle(px, py, qx, qy, rx, ry):
    """Circle through three points; degenerate (collinear) triples get an infinite radius."""
    bx, by = qx - px, qy - py
    cx, cy = rx - px, ry - py
    d = 2.0 * (bx * cy - by * cx)
    bb = bx * bx + by * by
    cc = cx * cx + cy * cy
    ok = np.abs(d) > 1e-14 * np.maximum(np.maximum(bb, cc), 1e-300)
    dsafe = np.where(ok, d, 1.0)
    ux = (cy * bb - by * cc) / dsafe
    uy = (bx * cc - cx * bb) / dsafe
    return px + ux, py + uy, np.where(ok, np.hypot(ux, uy), np.inf)


#: support points of the six candidate circles: (i, j) of the support, plus the new point
_PAIRS = np.array([[0, 0], [1, 1], [2, 2], [0, 1], [0, 2], [1, 2]])


def _smallest_with(sx: np.ndarray, sy: np.ndarray, qx: np.ndarray, qy: np.ndarray):
    """Smallest circle enclosing three support points (3, K) and q (K,), q on its boundary."""
    cand = []
    for i in range(3):
        cand.append(
            (0.5 * (sx[i] + qx), 0.5 * (sy[i] + qy), 0.5 * np.hypot(sx[i] - qx, sy[i] - qy))
        )
    for i, j in ((0, 1), (0, 2), (1, 2)):
        cand.append(_circumcircle(sx[i], sy[i], sx[j], sy[j], qx, qy))
    cx = np.stack([c[0] for c in cand])  # (6, K)
    cy = np.stack([c[1] for c in cand])
    r = np.stack([c[2] for c in cand])
    allx = np.concatenate([sx, qx[None]])  # (4, K)
    ally = np.concatenate([sy, qy[None]])
    dist = np.hypot(allx[None] - cx[:, None], ally[None] - cy[:, None])  # (6, 4, K)
    slack = INSIDE_TOLERANCE * np.where(np.isfinite(r), r, 0.0) + 1e-300
    encloses = np.all(dist <= (r + slack)[:, None], axis=1) & np.isfinite(r)
    best = np.argmin(np.where(encloses, r, np.inf), axis=0)  # (K,)
    k = np.arange(qx.size)
    i, j = _PAIRS[best, 0], _PAIRS[best, 1]
    new_sx = np.stack([sx[i, k], sx[j, k], qx])
    new_sy = np.stack([sy[i, k], sy[j, k], qy])
    return cx[best, k], cy[best, k], r[best, k], new_sx, new_sy


def minimum_circumscribed_circle_xy(x: np.ndarray, y: np.ndarray):
    """Centre (cx, cy) and radius of the smallest circle of each column set ``x``, ``y`` (m, K)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    cx, cy, radius, (ax, ay), (bx, by) = _initial_circle(x, y)
    # distances to points far from the origin carry round-off of their coordinates' size: a
    # point that far outside a tiny circle (two nearly equal stresses) is on it, not outside
    rounding = ROUNDING * (np.max(np.abs(x), axis=0) + np.max(np.abs(y), axis=0)) + 1e-300
    sx = np.stack([ax, bx, bx])
    sy = np.stack([ay, by, by])
    active = np.arange(x.shape[1])
    for _ in range(MAX_ROUNDS):
        if active.size == 0:
            break
        px, py = x[:, active], y[:, active]
        d = (px - cx[active]) ** 2 + (py - cy[active]) ** 2
        far = np.argmax(d, axis=0)
        cols = np.arange(active.size)
        dmax = np.sqrt(d[far, cols])
        outside = dmax > radius[active] * (1.0 + INSIDE_TOLERANCE) + rounding[active]
        active = active[outside]
        if active.size == 0:
            break
        qx, qy = px[far[outside], cols[outside]], py[far[outside], cols[outside]]
        ncx, ncy, nr, nsx, nsy = _smallest_with(sx[:, active], sy[:, active], qx, qy)
        cx[active], cy[active], radius[active] = ncx, ncy, nr
        sx[:, active], sy[:, active] = nsx, nsy
    else:  # pragma: no cover - the radius grows strictly, so this cannot be reached
        raise RuntimeError("minimum circumscribed circle did not converge")
    return cx, cy, radius


def minimum_circumscribed_circle(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre (K, 2) and radius (K,) of the smallest circle enclosing each set ``points`` (K, m, 2).

    Exact up to round-off (relative 1e-10). A set of identical points has radius 0.
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 3 or points.shape[2] != 2 or points.shape[1] < 1:
        raise ValueError(
            f"minimum_circumscribed_circle needs points of shape (K, m >= 1, 2), got {points.shape}"
        )
    cx, cy, radius = minimum_circumscribed_circle_xy(points[:, :, 0].T, points[:, :, 1].T)
    return np.stack([cx, cy], axis=1), radius
