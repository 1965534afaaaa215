"""A face whose x-projection is symmetric about its middle: half its node integrals.

The ln and sign integrals of a half-plane face depend only on x(xi), |dx/dxi| and the shape
functions (:mod:`fretbem.halfplane.influence`). Where the face's projection is its own
mirror image about its middle c (element e at local xi is element n_el - 1 - e at -xi,
function b is n - 1 - b, x goes to 2 c - x) and its nodes are mirrored alike, the kernels
ln|x_i - s| and sign(x_i - s) give

    L[n - 1 - i, n - 1 - b] = L[i, b],    S[n - 1 - i, n - 1 - b] = -S[i, b]

per coefficient, and so per unit node value (E is mirrored too). A symmetric pad or
specimen face (a cylinder, a rounded flat, a flat) then computes the first ceil(n / 2)
rows only, the rest mirrored: half the quadrature and half the solves through E^-1. The
mirrored rows equal the ones the face would compute to the round-off of its construction
(its control points, knots and nodes are symmetric to 1e-14 - 1e-13 of their scale).
"""

from __future__ import annotations

import numpy as np

from fretbem.basis import Basis, ElementMap

from .influence import SMOOTH_POINTS

#: a face is taken as symmetric when its mirrored projection (x about the middle, values,
#: dx/dxi) and node abscissae agree to this fraction of their scale: the round-off of a
#: symmetric construction (knot insertion, Greville abscissae) measured 1.5e-14 at 61
#: nodes and 1.5e-13 at 481 (in dx/dxi), far below the integrals' quadrature error
#: relative to their element (1e-14 of each element's integral, summed over the face)
TOLERANCE = 1e-12


def mirrored_rows(face, x: np.ndarray, mapped: ElementMap) -> int | None:
    """The number of leading node rows to compute (ceil(n / 2)) when ``face`` (with node
    abscissae ``x`` and its rule map ``mapped``, :func:`~fretbem.halfplane.influence.rule_map`)
    is mirror-symmetric about its middle; None when it is not (or is a joined face, or too
    small to gain). The integrals are functions of the node abscissae and of the face's
    projection alone: which element a node at an element end is given to does not matter."""
    n = x.size
    if not isinstance(face, Basis) or n < 4 or n != face.n_functions:
        return None
    connectivity = face.connectivity
    if not np.array_equal(connectivity[::-1, ::-1], n - 1 - connectivity):
        return None
    n_el, n_local = connectivity.shape
    centre = 0.5 * (x[0] + x[-1])
    span = abs(x[-1] - x[0])
    if not span > 0 or not np.all(np.abs((x[::-1] - centre) + (x - centre)) <= TOLERANCE * span):
        return None
    # the smooth-rule rows of the rule map: SMOOTH_POINTS Gauss points per element, placed
    # symmetrically in [-1, 1] (point q of element e mirrors point -1 - q of element -1 - e)
    rows = n_el * SMOOTH_POINTS
    xq = mapped.points[:rows, 0].reshape(n_el, SMOOTH_POINTS)
    if not np.all(np.abs((xq[::-1, ::-1] - centre) + (xq - centre)) <= TOLERANCE * span):
        return None
    dx = mapped.tangents[:rows, 0].reshape(n_el, SMOOTH_POINTS)
    if not np.all(np.abs(dx[::-1, ::-1] - dx) <= TOLERANCE * np.abs(dx).max()):
        return None
    values = mapped.values[:rows].reshape(n_el, SMOOTH_POINTS, n_local)
    if not np.all(np.abs(values[::-1, ::-1, ::-1] - values) <= TOLERANCE):
        return None
    return (n + 1) // 2


def mirrored(both: np.ndarray, n: int) -> np.ndarray:
    """The (2 n, n) stacked ln and sign integrals per node value from the (2 h, n) ones of
    the first h = ceil(n / 2) nodes: the rest mirrored (the sign integrals negated)."""
    h = both.shape[0] // 2
    log, sign = both[:h], both[h:]
    out = np.empty((2 * n, n))
    out[:h] = log
    out[h:n] = log[: n - h][::-1, ::-1]
    out[n : n + h] = sign
    np.negative(sign[: n - h][::-1, ::-1], out=out[n + h :])
    return out
