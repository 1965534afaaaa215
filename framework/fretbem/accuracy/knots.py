"""Transition points of a contact history and the moves that put C0 knots on them.

:func:`transitions` finds, from any solved level, the contact edges (p falls to zero like a
square root) and the stick-slip boundaries (the traction reserve f p - abs(q) does). On an
aligned level each transition carries a collocation point on a C0 knot; :func:`knot_moves`
says how far each knot lies from the level's own discrete transition, from both sides
(docs/explanation/adaptive.rst, "Moving the knots").
"""

from __future__ import annotations

import itertools
import math
import weakref

import attrs
import numpy as np

from fretbem.contact.pairs import PairState

from . import estimate
from .remesh import MERGE

__all__ = [
    "EDGE_MARGIN",
    "KNOT_SLOPE",
    "Transitions",
    "fit_transitions",
    "knot_moves",
    "knot_pressures",
    "knot_spacings",
    "refound",
    "transitions",
]

#: the pair states as plain ints: numpy compares an IntEnum member only after asking its
#: class for the array protocols (~2 us a comparison, thousands per adaptive run)
SEPARATED, STICK, SLIP = (int(s) for s in (PairState.SEPARATED, PairState.STICK, PairState.SLIP))

#: knots aim this fraction of the spacing of the points next to them outside their discrete
#: transition (on the separated or slip side): a collocation point just inside the exact
#: transition sees a square root of the distance, one just outside costs little. A fraction
#: of the spacing, not of the contact width: a fixed 0.1 % of a was 0.15 of the spacing at
#: 61 pairs and 0.37 at 121, where the knot a margin off the cusp gave e_q 1.1 % against
#: 0.6 % (docs/explanation/adaptive.rst)
EDGE_MARGIN = 0.1

#: the first (uniform) level's edges are moved out by this fraction of the contact
#: half-width: its points are too far apart for a margin in units of their spacing
FIRST_MARGIN = 1e-3

#: the traction (pressure, or reserve f p - abs(q)) at a collocation point on a C0 knot a
#: distance d inside its discrete transition is about KNOT_SLOPE * A * d / sqrt(h) (A:
#: amplitude of A sqrt(distance), h: the element inside); measured 1.4 to 1.9 on the
#: reference scene at 31 to 61 pairs
KNOT_SLOPE = 1.6

#: the gap outside a contact edge and the slip increment outside a stick zone grow like
#: distance^GROWTH from the transition (Hertz; Cattaneo-Mindlin)
GROWTH = 1.5


def _polyfit(x: np.ndarray, y: np.ndarray, degree: int) -> np.ndarray:
    """``np.polyfit(x, y, degree)`` (degree 1 or 2), the same arithmetic bit for bit (the
    scaled Vandermonde columns and the one least-squares solve) without its argument
    checks and general Vandermonde: the adaptive mode fits ~90 of them a run. The solve is
    numpy's own LAPACK routine (:data:`_LSTSQ`, what ``np.linalg.lstsq`` calls) without
    the wrapper's checks, for finite data (others take ``np.linalg.lstsq``, and its error)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    lhs = np.empty((x.size, degree + 1))  # C-ordered as np.vander's: the column sums alike
    if degree == 2:
        lhs[:, 0] = x * x
    lhs[:, degree - 1] = x
    lhs[:, degree] = 1.0
    scale = np.sqrt((lhs * lhs).sum(axis=0))
    lhs /= scale
    rcond = x.size * _EPS
    if _LSTSQ is not None and math.isfinite(float(lhs.sum()) + float(y.sum())):
        coefficients = _LSTSQ(lhs, y[:, None], rcond, signature="ddd->ddid")[0][:, 0]
    else:
        coefficients = np.linalg.lstsq(lhs, y, rcond=rcond)[0]
    return coefficients / scale


_EPS = float(np.finfo(float).eps)

#: the gufuncs ``np.linalg.lstsq`` and ``np.linalg.eigvals`` call (numpy's LAPACK
#: wrappers), or None where this numpy has them elsewhere: a fit then takes the public
#: function, the same numbers at twice the time (~20 us of checks a call)
_UMATH_LINALG = getattr(np.linalg, "_umath_linalg", None)
_LSTSQ = getattr(_UMATH_LINALG, "lstsq", None)
_EIGVALS = getattr(_UMATH_LINALG, "eigvals", None)


def _polyroots(coefficients: np.ndarray) -> np.ndarray:
    """``np.roots(coefficients)`` of a line or quadratic with nonzero ends: the eigenvalues
    of the same companion matrix, built directly, by the routine ``np.linalg.eigvals``
    calls (np.roots otherwise)."""
    if coefficients[0] == 0.0 or coefficients[-1] == 0.0:
        return np.roots(coefficients)
    companion = np.zeros((coefficients.size - 1, coefficients.size - 1))
    companion[0, :] = -coefficients[1:] / coefficients[0]
    if coefficients.size == 3:
        companion[1, 0] = 1.0
    if _EIGVALS is None or not math.isfinite(float(companion.sum())):
        return np.linalg.eigvals(companion)
    values = _EIGVALS(companion, signature="d->D")
    return values.real if not values.imag.any() else values


def _root_of_square(x: np.ndarray, values: np.ndarray, towards: float) -> float | None:
    """Zero of a quadratic fit of values^2 (a square-root fall to zero) nearest ``towards``."""
    if x.size < 2:
        return None
    # a square-root fall squared is quadratic (Hertz, exactly) and linear near its zero
    coefficients = _polyfit(x, values**2, 2 if x.size >= 4 else 1)
    roots = _polyroots(coefficients)
    roots = roots[np.isreal(roots)].real
    if roots.size == 0:
        return None
    return float(roots[np.argmin(np.abs(roots - towards))])


def _edge(x, p, inside: np.ndarray, side: int, gap: float) -> float:
    """Contact edge on one side: p^2 fitted over the outer contact nodes, else the midpoint."""
    k = np.flatnonzero(inside)
    last = k[-1] if side > 0 else k[0]
    beyond = last + side
    midpoint = (
        x[last] + 0.5 * side * gap if not (0 <= beyond < x.size) else 0.5 * (x[last] + x[beyond])
    )
    width = x[k[-1]] - x[k[0]]
    near = k[np.abs(x[k] - x[last]) <= 0.4 * width]
    root = _root_of_square(x[near], p[near], x[last])
    limit = x[beyond] if 0 <= beyond < x.size else x[last] + side * gap
    if root is None or not (min(x[last], limit) - 1e-12 <= root <= max(x[last], limit) + 1e-12):
        return float(midpoint)
    return root


def _stick_boundaries(x, p, q, states, friction) -> list[float]:
    """Boundaries between a stick run and its slip neighbours, from the traction reserve."""
    out = []
    stick = states == 1
    slip = states == 2
    n = x.size
    changes = (stick[:-1] & slip[1:]) | (slip[:-1] & stick[1:])
    for i in np.flatnonzero(changes).tolist():
        a, b = i, i + 1
        s, k = (a, b) if stick[a] else (b, a)  # s stick, k slip
        direction = np.sign(q[k]) or 1.0
        reserve = np.maximum(friction * p - direction * q, 0.0)
        # the stick run that ends at s, toward the slip node k
        step = -1 if k > s else 1
        run = [s]
        j = s + step
        while 0 <= j < n and stick[j] and len(run) < 3:
            run.append(j)
            j += step
        run = np.array(run)
        root = _root_of_square(x[run], reserve[run], x[s])
        lo, hi = sorted((x[s], x[k]))
        if root is None or not (lo <= root <= hi):
            root = 0.5 * (x[s] + x[k])
        out.append(float(root))
    return out


def _merge(values: list[float], tolerance: float) -> np.ndarray:
    """Sorted values with those closer than ``tolerance`` averaged into one."""
    merged: list[float] = []
    for value in np.sort(np.array(values, float)):
        if merged and value - merged[-1] < tolerance:
            merged[-1] = 0.5 * (merged[-1] + value)
        else:
            merged.append(float(value))
    return np.array(merged)


@attrs.frozen(eq=False)
class Transitions:
    """Transition points of a whole history, positions along the contact face.

    Attributes
    ----------
    edges : ndarray
        Contact edges of every step (moved out by :data:`EDGE_MARGIN`).
    boundaries : ndarray
        Stick-slip and reverse-slip boundaries of every step.
    """

    edges: np.ndarray
    boundaries: np.ndarray

    @property
    def all(self) -> np.ndarray:
        """Edges and boundaries together, sorted."""
        return np.sort(np.concatenate([self.edges, self.boundaries]))


def transitions(result) -> Transitions:
    """Contact edges and stick-slip boundaries of every step of a result.

    Edges from a quadratic fit of p^2 over the outer contact nodes (exact for a Hertzian
    pressure); stick-slip boundaries from a linear fit of the squared traction reserve
    f p - abs(q) over the three stick nodes next to the slip zone (a square-root fall squared
    is linear near its zero). Falls back to the midpoint between the nodes on either side
    where a fit is not possible.
    """
    level = _level(result)
    x, gap = level.x, level.spacing
    friction = estimate.friction_of(result.simulation)
    edges: list[float] = []
    boundaries: list[float] = []
    for step in level.steps:
        p, q, states = step.pressure, step.shear, step.states
        inside = states != SEPARATED
        if not inside.any():
            continue
        k = np.flatnonzero(inside)
        margin = FIRST_MARGIN * 0.5 * (x[k[-1]] - x[k[0]])
        for side in (-1, 1):
            edges.append(_edge(x, p, inside, side, gap) + side * margin)
        boundaries += _stick_boundaries(x, p, q, states, friction)
    tolerance = MERGE * (x[-1] - x[0])
    return Transitions(_merge(edges, tolerance), _merge(boundaries, tolerance))


def refound(level, settled: Transitions, reach: float) -> Transitions:
    """The transitions of a settled ``level``, each on its settled knot where one lies
    within ``reach``: a level that could place only some knots (:func:`fit_transitions`)
    hands every transition on to the next, finer one, the settled ones where they settled."""
    fresh = transitions(level)

    def carry(values: np.ndarray, knots: np.ndarray) -> np.ndarray:
        out = []
        for value in values:
            near = knots[np.abs(knots - value) <= reach] if knots.size else knots
            out.append(float(near[np.argmin(np.abs(near - value))]) if near.size else value)
        return np.unique(np.concatenate([out, knots])) if knots.size else np.array(out)

    return Transitions(
        carry(fresh.edges, settled.edges), carry(fresh.boundaries, settled.boundaries)
    )


def fit_transitions(found: Transitions, most: int) -> Transitions:
    """``found`` with at most ``most`` knots: the closest two merged until they fit.

    A face holds only so many C0 knots (each costs a collocation point and needs an element
    on either side); dissimilar materials have many transitions (a slip zone at each edge
    and a central stick zone at every step, each step's a little apart). Two boundaries or
    two edges merge into their middle; an edge and a boundary into the edge (the pressure's
    square root matters to p and q, the cusp of q to q alone).
    """
    most = max(int(most), 0)
    kinds = [(float(v), "edge") for v in found.edges] + [
        (float(v), "boundary") for v in found.boundaries
    ]
    kinds.sort()
    if most == 0:
        return Transitions(np.zeros(0), np.zeros(0))
    while len(kinds) > most:
        gaps = [b[0] - a[0] for a, b in itertools.pairwise(kinds)]
        i = int(np.argmin(gaps))
        (xa, ka), (xb, kb) = kinds[i], kinds[i + 1]
        if ka == kb:
            merged = (0.5 * (xa + xb), ka)
        else:
            merged = (xa, ka) if ka == "edge" else (xb, kb)
        kinds[i : i + 2] = [merged]
    edges = np.array([v for v, k in kinds if k == "edge"])
    boundaries = np.array([v for v, k in kinds if k == "boundary"])
    return Transitions(edges, boundaries)


# -- a level's pairs in order along the face ----------------------------------------------------
@attrs.frozen(eq=False)
class _SortedStep:
    """One step's pair results in the order of the pairs along the face (read-only)."""

    states: np.ndarray
    pressure: np.ndarray
    shear: np.ndarray
    slip: np.ndarray  # tangential_displacement
    increment: np.ndarray  # abs(slip - the step before's slip), the first step's from 0
    gap: np.ndarray  # initial gap + normal_displacement


@attrs.frozen(eq=False)
class _SortedLevel:
    """A solved level's pair positions along the face (sorted), the sort order, the smallest
    spacing and every step's results in that order."""

    x: np.ndarray
    order: np.ndarray
    spacing: float
    steps: tuple


#: each solved level's :class:`_SortedLevel` (weak keys: it goes with the result); the
#: transitions, knot moves and spacings of a level ask for it up to ten times
_LEVELS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _level(result) -> _SortedLevel:
    """``result`` in the order of its pairs along the face, kept per result."""
    level = _LEVELS.get(result)
    if level is not None:
        return level
    along = estimate.positions(result)
    order = np.argsort(along)
    x = along[order]
    initial = np.asarray(result.simulation.pair.pairing().gap, float)[order]
    steps, previous = [], np.zeros(x.size)
    for step in result.steps:
        slip = step.tangential_displacement[order]
        sorted_step = _SortedStep(
            states=step.states[order],
            pressure=step.pressure[order],
            shear=step.shear[order],
            slip=slip,
            increment=np.abs(slip - previous),
            gap=initial + step.normal_displacement[order],
        )
        previous = slip
        for array in attrs.astuple(sorted_step, recurse=False):
            array.flags.writeable = False
        steps.append(sorted_step)
    x.flags.writeable = order.flags.writeable = False
    level = _SortedLevel(x, order, float(np.min(np.diff(x))), tuple(steps))
    _LEVELS[result] = level
    return level


# -- knots on the transitions of an aligned level --------------------------------------------


def _knot_index(x: np.ndarray, knot: float, spacing: float) -> int | None:
    """Index of the collocation point on ``knot``, None if no point is on it."""
    k = int(np.argmin(np.abs(x - knot)))
    return k if abs(x[k] - knot) <= 1e-3 * spacing else None


def _inside_move(x, values, k: int, towards: int) -> float | None:
    """Distance from point k (value > 0 on a C0 knot) out to the discrete zero, ``towards``
    the zero: values = A sqrt(distance) fitted over three points behind k (KNOT_SLOPE)."""
    near = [k - towards, k - 2 * towards, k - 3 * towards]
    if min(near) < 0 or max(near) >= x.size or values[k] <= 0.0:
        return None
    slope = abs(_polyfit(x[near], values[near] ** 2, 1)[0])
    if slope <= 0.0:
        return None
    h = abs(x[k] - x[k - towards])
    return float(values[k] * math.sqrt(h) / (KNOT_SLOPE * math.sqrt(slope)))


def _outside_move(x, values, k: int, away: int) -> float | None:
    """Distance from point k back to the transition behind it, from values growing like
    distance^GROWTH at k and at the next point ``away`` from the transition."""
    o = k + away
    if not (0 <= o < x.size) or values[k] <= 0.0 or values[o] <= values[k]:
        return None
    r = (values[k] / values[o]) ** (1.0 / GROWTH)
    return float(r * abs(x[o] - x[k]) / (1.0 - r))


def _edge_move(level: _SortedLevel, knot, k, margin: float) -> float | None:
    """Move of an edge knot to ``margin`` outside the discrete edge, from the steps whose
    contact ends at its point or just inside it."""
    x = level.x
    side = 1 if knot > 0.5 * (x[0] + x[-1]) else -1
    inner, outer = k - side, k + side
    if not (0 <= inner < x.size):
        return None
    out, into = [], []
    for step in level.steps:
        states, p, gap = step.states, step.pressure, step.gap
        contact = states != SEPARATED
        beyond = not (0 <= outer < x.size) or not contact[outer]
        if contact[k] and beyond:  # the last contact point: pressure says how far out
            move = _inside_move(x, p, k, side)
            if move is not None:
                reach = abs(x[outer] - x[k]) if 0 <= outer < x.size else move
                out.append(min(move, 0.9 * reach))
        elif not contact[k] and contact[inner]:  # first separated point: the gap says how far in
            move = _outside_move(x, gap, k, side)
            if move is not None:
                into.append(min(move, 0.9 * abs(x[k] - x[inner])))
    if out:
        return side * (max(out) + margin)
    if into:
        return -side * (min(into) - margin)
    return None


def _boundary_move(level: _SortedLevel, k, friction, margin: float) -> float | None:
    """Move of a stick-slip knot to ``margin`` on the slip side of the discrete boundary: the
    reserve on its point if stick, the slip increment if slip, averaged over the steps whose
    stick-slip boundary is next to its point."""
    x = level.x
    moves = []
    for step in level.steps:
        states, increment = step.states, step.increment
        p, q = step.pressure, step.shear
        for t in (-1, 1):  # t: direction from the stick side to the slip side
            j = k + t
            if not (0 <= j < x.size and 0 <= k - t < x.size):
                continue
            if states[k] == STICK and states[j] == SLIP:
                direction = np.sign(q[j]) or 1.0
                reserve = np.maximum(friction * p - direction * q, 0.0)
                move = _inside_move(x, reserve, k, t)
                if move is not None:
                    moves.append(t * (min(move, 0.9 * abs(x[j] - x[k])) + margin))
            elif states[k] == SLIP and states[k - t] == STICK:
                move = _outside_move(x, increment, k, t)
                if move is not None:
                    moves.append(-t * (min(move, 0.9 * abs(x[k] - x[k - t])) - margin))
    return float(np.mean(moves)) if moves else None


def knot_spacings(result, found: Transitions) -> np.ndarray:
    """Distance from each knot's point to its nearer neighbour point (edges, then
    boundaries); the contact half-width where no point is on the knot."""
    level = _level(result)
    x, spacing = level.x, level.spacing
    half = 0.5 * float(x[-1] - x[0])
    out = []
    for knot in np.concatenate([found.edges, found.boundaries]):
        k = _knot_index(x, knot, spacing)
        if k is None:
            out.append(half)
            continue
        near = [abs(x[j] - x[k]) for j in (k - 1, k + 1) if 0 <= j < x.size]
        out.append(min(near))
    return np.array(out)


def knot_moves(
    result, found: Transitions, reach: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Signed moves (along the face) of the edge and boundary knots onto the level's own
    discrete transitions; 0 where a knot has no point or no transition next to it.

    A knot point still inside its transition carries pressure (edges) or traction reserve
    (stick-slip) that grows linearly with the distance (:data:`KNOT_SLOPE`); one outside it
    carries a gap or a slip increment growing like distance^1.5 (:data:`GROWTH`). Each
    knot aims :data:`EDGE_MARGIN` times its point spacing outside its transition. A knot
    with no transition next to its point moves to the middle of the nearest one; with
    ``reach`` (in its point spacings, e.g. :data:`FALLBACK_REACH`) a stick-slip knot does
    so only if that one is closer, else it stays (edge knots always move).
    """
    level = _level(result)
    x, spacing = level.x, level.spacing
    friction = estimate.friction_of(result.simulation)
    spacings = knot_spacings(result, found)
    margins = EDGE_MARGIN * spacings
    states = [step.states for step in level.steps]
    edges = np.zeros(found.edges.size)
    for j, knot in enumerate(found.edges):
        k = _knot_index(x, knot, spacing)
        margin = margins[j]
        move = None if k is None else _edge_move(level, knot, k, margin)
        if move is None:
            move = _nearest_change(x, states, knot, SEPARATED, (STICK, SLIP)) - knot
        edges[j] = move
    boundaries = np.zeros(found.boundaries.size)
    for j, knot in enumerate(found.boundaries):
        k = _knot_index(x, knot, spacing)
        margin = margins[found.edges.size + j]
        move = None if k is None else _boundary_move(level, k, friction, margin)
        if move is None:
            spacing = spacings[found.edges.size + j]
            move = _fallback(x, states, knot, k, spacing, reach, SLIP, (STICK,))
        boundaries[j] = move
    return edges, boundaries


#: a stick-slip knot on a point with no stick-slip boundary next to it moves to the nearest
#: one only within this many of its point spacings; farther, that boundary is another
#: knot's and the knot stays where the coarser level put it. Unbounded, the rig's step E
#: knot (0.661 mm, its slip zone narrower than a spacing at 83 pairs) walked onto step A's
#: boundary at 0.653 mm and q away from the transitions rose 0.39 -> 0.93 % from budget 71
#: to 83; bounded, 0.39 -> 0.38 %. Only on levels whose knots a settled node-to-node level
#: of at least ``first`` pairs handed on (coarser ones misplace knots by more: bounded
#: there, the rig at 31 pairs rose 4.0 -> 9.6 %), and not for edge knots (bounded, steel
#: on aluminium at 161 pairs rose 0.22 -> 0.65 %); docs/explanation/adaptive.rst, "Limits"
FALLBACK_REACH = 1.5


def _fallback(x, states, knot: float, k, spacing: float, reach, outer: int, inner: tuple):
    """Move of a knot with no transition next to its point: to the nearest state change if
    the knot has no point, ``reach`` is None or the change lies within ``reach`` spacings,
    else 0."""
    move = _nearest_change(x, states, knot, outer, inner) - knot
    if k is not None and reach is not None and abs(move) > reach * spacing:
        return 0.0
    return move


def _nearest_change(x, states, knot: float, outer: int, inner: tuple) -> float:
    """Midpoint of the two points where the state changes between ``inner`` and ``outer``
    nearest ``knot`` over the steps; ``knot`` itself if there is none."""
    best = knot
    for st in states:
        a, b = st[:-1], st[1:]
        change = ((a == outer) & np.isin(b, inner)) | (np.isin(a, inner) & (b == outer))
        for i in np.flatnonzero(change):
            middle = 0.5 * float(x[i] + x[i + 1])
            if best == knot or abs(middle - knot) < abs(best - knot):
                best = middle
    return best


def knot_pressures(result, edges: np.ndarray) -> np.ndarray:
    """Largest pressure over the steps at the point on each edge knot (0 if separated)."""
    level = _level(result)
    x, spacing = level.x, level.spacing
    out = np.zeros(len(edges))
    for j, edge in enumerate(edges):
        k = _knot_index(x, edge, spacing)
        if k is None:
            continue
        for step in level.steps:
            if step.states[k] != SEPARATED:
                out[j] = max(out[j], float(step.pressure[k]))
    return out
