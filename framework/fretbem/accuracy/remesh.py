"""Aligned contact meshes: both contact faces re-meshed with C0 knots on given positions.

Elements are graded toward the transition points (contact edges, stick-slip boundaries) and
each becomes a breakpoint where the basis is only C0, which puts a collocation point on it
(docs/explanation/adaptive.rst). Used by :mod:`fretbem.accuracy.adaptive`.
"""

from __future__ import annotations

import functools
import math
import weakref

import attrs
import numpy as np

from fretbem.basis import Refinement, face_points, points_per_element
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairs import ContactDiscretisationError
from fretbem.errors import InputError
from fretbem.geometry import knots as kv
from fretbem.geometry.nurbs import NurbsCurve

from . import estimate

__all__ = [
    "AdaptiveError",
    "aligned_breakpoints",
    "elements_for",
    "knots_for",
    "pairs_for",
    "remesh",
]

#: smallest transition spacing kept apart, as a fraction of the face length
MERGE = 2e-3

#: how far (fraction of the face's parameter, or of its size) a face, a layout or a set of
#: anchors may be from its mirror image about the face's middle and still count as
#: symmetric (round-off: the reference pad is symmetric to 1.5e-14 of its height)
SYMMETRY_TOLERANCE = 1e-11

#: where :func:`aligned_breakpoints` integrates the element density (read-only)
_GRID = np.linspace(0.0, 1.0, 8001)
_GRID.flags.writeable = False
#: its spacings (``np.diff(_GRID)``, read-only)
_GRID_STEPS = np.diff(_GRID)
_GRID_STEPS.flags.writeable = False


class AdaptiveError(InputError):
    """Settings, a face or a layout the adaptive mode cannot work with."""


def aligned_breakpoints(
    anchors: np.ndarray,
    elements: int,
    *,
    ratio: float = 4.0,
    grading: float = 0.15,
    centred: bool = False,
    peaks: np.ndarray | None = None,
    symmetric: bool = False,
) -> np.ndarray:
    """Breakpoints in [0, 1]: ``elements`` elements, graded toward ``anchors``.

    Each anchor is a breakpoint, or with ``centred`` the centre of an element. Element
    density falls linearly with the distance to an anchor, from ``peaks`` (default 1) at it
    to 1 / ``ratio`` at ``grading`` (fraction of [0, 1]) and beyond; the gaps between
    anchors get whole numbers of elements that equidistribute it. With ``symmetric``
    (anchors and peaks symmetric about 1/2, as :func:`symmetric_anchors` makes them) mirrored
    gaps get the same count and the breakpoints are symmetric exactly (b = 1 - b reversed);
    an odd ``elements`` with no gap in the middle gets one element fewer.
    """
    anchors = np.asarray(anchors, float)
    peaks = np.ones(anchors.size) if peaks is None else np.asarray(peaks, float)
    order = np.argsort(anchors)
    anchors, peaks = anchors[order], peaks[order]
    keep = (anchors > MERGE) & (anchors < 1.0 - MERGE)
    anchors, peaks = anchors[keep], peaks[keep]
    if anchors.size > 1:  # coincident transitions share one anchor
        keep = np.concatenate([[True], np.diff(anchors) > MERGE])
        anchors, peaks = anchors[keep], peaks[keep]
    m = anchors.size
    fixed = m if centred else 0
    if elements < m + 1 + fixed:
        raise AdaptiveError(
            f"{elements} elements cannot place {m} transitions with an element between "
            "them; raise the pair budget"
        )
    if m == 0:
        return np.linspace(0.0, 1.0, elements + 1)
    grid = _GRID
    cumulative = _cumulative_density(anchors, peaks, ratio, grading)
    spacing = np.diff(np.concatenate([[-anchors[0]], anchors, [2.0 - anchors[-1]]]))
    room = 0.3 * np.minimum(spacing[:-1], spacing[1:])

    def layout(h):
        half = np.minimum(0.5 * h, room) if centred else np.zeros(m)
        starts = np.concatenate([[0.0], anchors + half])
        ends = np.concatenate([anchors - half, [1.0]])
        work = (np.interp(ends, grid, cumulative) - np.interp(starts, grid, cumulative)) / h
        return half, starts, ends, work

    # without centring the gaps do not depend on h: their integrals are taken once
    fixed_work = None if centred else layout(1.0)[3]
    target = elements - fixed
    lo_h, hi_h = 1e-7, 2.0
    gaps = None if centred else fixed_work.tolist()
    for _ in range(80):
        h = math.sqrt(lo_h * hi_h)
        if centred:
            above = np.maximum(layout(h)[3], 1.0).sum() > target
        else:
            above = _exceeds(gaps, h, fixed_work, target)
        bracket = (h, hi_h) if above else (lo_h, h)
        if bracket == (lo_h, hi_h):  # a fixed point: the remaining rounds would repeat it
            break
        lo_h, hi_h = bracket
    _, starts, ends, work = layout(math.sqrt(lo_h * hi_h))
    if symmetric:
        counts = _symmetric_counts(0.5 * (work + work[::-1]), target)
    else:
        counts = np.maximum(np.floor(work), 1).astype(int)
        while counts.sum() < target:
            counts[np.argmax(work - counts)] += 1
        while counts.sum() > target:
            spare = np.where(counts > 1, counts - work, -np.inf)
            counts[np.argmax(spare)] -= 1
    # each gap's points equidistribute the density integral; np.interp maps every value
    # on its own, so all gaps go through it at once
    ends_at = np.interp(np.concatenate([starts, ends]), grid, cumulative).tolist()
    levels = [np.zeros(1)]
    levels += [
        np.linspace(ca, cb, n + 1)
        for ca, cb, n in zip(ends_at[: starts.size], ends_at[starts.size :], counts, strict=True)
    ]
    points = np.interp(np.concatenate(levels), cumulative, grid)
    points[0] = 0.0
    first = np.cumsum([1, *(n + 1 for n in counts[:-1].tolist())])
    points[first], points[first + counts] = starts, ends
    out = np.unique(points)
    out[0], out[-1] = 0.0, 1.0
    return _mirrored(out) if symmetric else out


#: the last few element densities' integrals over the grid (a face laid out for several
#: element counts toward the same anchors: the fitting layouts of one level)
_DENSITIES: dict = {}


def _cumulative_density(anchors, peaks, ratio: float, grading: float) -> np.ndarray:
    """The integral over :data:`_GRID` of the element density toward ``anchors`` (sorted and
    merged), kept for the last few anchor sets (read-only)."""
    key = (anchors.tobytes(), peaks.tobytes(), float(ratio), float(grading))
    if key in _DENSITIES:
        return _DENSITIES[key]
    slope = (ratio - 1.0) / grading
    grid = _GRID
    # the density of the nearest anchor, anchor by anchor over the grid (the same values
    # as one (grid, anchors) array's row maxima, without its strided reduction), each
    # compared only where it can exceed the floor 1 / ratio: within (peak ratio - 1) / slope
    # of its anchor (a thousandth more: outside, it lies below the floor by far more than
    # round-off), a sixth of the grid at the adaptive levels' ratio and grading
    rho = np.full(grid.size, 1.0 / ratio)
    for anchor, peak in zip(anchors, peaks, strict=True):
        part = slice(None)
        reach = 1.001 * (peak * ratio - 1.0) / slope if slope > 0.0 else math.inf
        if peak * ratio > 1.0 + 1e-6 and math.isfinite(reach):
            lo, hi = np.searchsorted(grid, (anchor - reach, anchor + reach))
            part = slice(int(lo), int(hi))
        near = grid[part]
        np.maximum(rho[part], peak / (1.0 + slope * np.abs(near - anchor)), out=rho[part])
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (rho[1:] + rho[:-1]) * _GRID_STEPS)])
    cumulative.flags.writeable = False
    if len(_DENSITIES) >= 8:
        _DENSITIES.pop(next(iter(_DENSITIES)))
    _DENSITIES[key] = cumulative
    return cumulative


def _exceeds(gaps: list, h: float, fixed_work: np.ndarray, target: int) -> bool:
    """Whether ``np.maximum(fixed_work / h, 1.0).sum() > target`` (``gaps``: fixed_work's
    entries as floats): the same entries in floats, summed in order, and only when that sum
    is within its rounding bound of the target summed again as numpy does (pairwise), so the
    answer is numpy's at a fraction of its cost (the bisection asks up to 80 times)."""
    total = 0.0
    for g in gaps:
        w = g / h
        if w != w:  # NaN: numpy's maximum keeps it
            return bool(np.maximum(fixed_work / h, 1.0).sum() > target)
        total += w if w > 1.0 else 1.0
    if abs(total - target) > 4.0 * (len(gaps) + 1) * _EPS * total:
        return total > target
    return bool(np.maximum(fixed_work / h, 1.0).sum() > target)


_EPS = float(np.finfo(float).eps)


def _symmetric_counts(work: np.ndarray, target: int) -> np.ndarray:
    """Whole element counts of gaps mirrored about the middle (``work`` symmetric), the
    same in each mirrored pair, at most ``target`` in all: the rounding of the free
    layout, each change made to a gap and its mirror together (the middle gap alone)."""
    counts = np.maximum(np.floor(work), 1).astype(int)
    size = work.size
    half = np.arange((size + 1) // 2)  # a gap of each mirrored pair (and the middle one)
    step = np.where(half == size - 1 - half, 1, 2)
    while True:
        room = target - counts.sum()
        if room <= 0:
            break
        gain = np.where(step <= room, (work - counts)[half], -np.inf)
        if not np.isfinite(gain).any():
            break
        i = int(np.argmax(gain))
        counts[half[i]] += 1
        counts[size - 1 - half[i]] += step[i] - 1
    while counts.sum() > target:
        spare = np.where(counts[half] > 1, (counts - work)[half], -np.inf)
        if not np.isfinite(spare).any():
            break
        i = int(np.argmax(spare))
        counts[half[i]] -= 1
        counts[size - 1 - half[i]] -= step[i] - 1
    return counts


def _mirrored(bounds: np.ndarray) -> np.ndarray:
    """Breakpoints symmetric about 1/2 to round-off made so exactly: the right half is the
    left one mirrored (1 - b), and a middle breakpoint is 1/2 (``bounds`` as they are if
    they are not symmetric: anchors merged on one side only)."""
    n = bounds.size
    if np.abs(bounds + bounds[::-1] - 1.0).max() > SYMMETRY_TOLERANCE:
        return bounds
    left = bounds[: n // 2]
    middle = [0.5] if n % 2 else []
    return np.concatenate([left, middle, (1.0 - left)[::-1]])


#: pairs a family puts on a face of that many elements (the discretisation's own count)
pairs_for = face_points


def elements_for(family, pairs: int, degree: int | None = None) -> int:
    """Most elements whose face has at most ``pairs`` collocation points."""
    per, extra = points_per_element(family, degree)
    return max(1, math.floor((pairs - extra) / per))


def knots_for(family, pairs: int, degree: int | None = None) -> int:
    """Most C0 knots a face of at most ``pairs`` points can place, an element between each.

    Each knot costs the family's extra functions of a C0 breakpoint (NURBS p = 2: one;
    quadratic Lagrange: none) and the layout needs one element more than knots.
    """
    cost = c0_cost(family, degree) / points_per_element(family, degree)[0]
    elements = elements_for(family, pairs, degree)
    return max(0, math.floor((elements - 1) / (1.0 + cost)))


@functools.lru_cache(maxsize=64)
def c0_cost(family, degree: int | None = None) -> int:
    """Functions (points) a C0 breakpoint adds to a family's face (NURBS p: p - 1;
    quadratic Lagrange: none), counted on a four-element line (cached)."""
    line = NurbsCurve.line([0, 0], [1, 0], degree=1)
    bounds = [0.0, 0.25, 0.5, 0.75, 1.0]
    smooth = family.discretise(line, Refinement.explicit(bounds, degree=degree)).n_functions
    kinked = family.discretise(line, Refinement.explicit(bounds, degree=degree, c0_at=[0.5]))
    return int(kinked.n_functions - smooth)


def _fitting_elements(family, degree, pairs: int, curve, marks_of, count_of) -> int:
    """Elements of a face laid out with at most ``pairs`` points: from
    :func:`elements_for` down, fewer by as many elements as the points in excess need,
    until the face fits (each C0 mark adds :func:`c0_cost` points).

    ``marks_of(elements)`` counts the C0 marks of that layout, ``count_of(elements)`` builds
    it and counts its points. On a face curve without interior knots a family's count is
    that of a line of as many elements plus the marks' cost, so the layouts that do not fit
    are counted without building them and only the one that fits is built (and checked: a
    count other than foreseen goes through every layout's build, as when the curve has
    knots of its own).
    """
    per, _ = points_per_element(family, degree)

    def settle(count) -> tuple[int, int]:
        elements = elements_for(family, pairs, degree)
        while True:
            points = count(elements)
            if points <= pairs or elements <= 1:
                return elements, points
            elements -= max(1, math.ceil((points - pairs) / per))

    if kv.breakpoints(curve.knots).size == 2:
        cost = c0_cost(family, degree)
        elements, foreseen = settle(lambda n: face_points(family, n, degree) + cost * marks_of(n))
        if count_of(elements) == foreseen:
            return elements
    return settle(count_of)[0]


def _marks_count(sigma: np.ndarray, centred: bool) -> int | None:
    """The C0 marks of every layout toward anchors at parameters ``sigma`` (in the layout's
    own parameter), without laying one out: one per anchor when each stays a breakpoint of
    its own (inside (MERGE, 1 - MERGE) and farther than MERGE from the next:
    :func:`aligned_breakpoints` keeps it, with an element either side, so the breakpoint
    nearest it is its own); None when a layout must say (centred, or an anchor merged or
    dropped, whose mark is whichever breakpoint lies nearest)."""
    if centred:
        return None
    values = np.sort(np.asarray(sigma, float))
    if values.size and (
        values[0] <= MERGE or values[-1] >= 1.0 - MERGE or np.any(np.diff(values) <= MERGE)
    ):
        return None
    return int(values.size)


def _fitted_layout(family, degree, pairs: int, curve, layout, count, marks: int | None):
    """``layout(elements)`` of the most elements whose face holds at most ``pairs`` points
    (:func:`_fitting_elements`). ``marks`` (:func:`_marks_count`, or None) counts the C0 marks
    of every layout, so that the layouts that do not fit are never built (a level's first
    guess rarely fits: each knot costs a point); the one that fits is checked against it,
    and a count other than foreseen goes through every layout's own."""
    foreseen = [marks]

    def marks_of(elements):
        if foreseen[0] is None or elements < foreseen[0] + 1:  # too few: its layout says why
            return len(layout(elements).c0_at)
        return foreseen[0]

    elements = _fitting_elements(family, degree, pairs, curve, marks_of, count)
    if foreseen[0] is not None and len(layout(elements).c0_at) != foreseen[0]:
        foreseen[0] = None
        elements = _fitting_elements(family, degree, pairs, curve, marks_of, count)
    return layout(elements)


def _face_layout(body, tag, tangent, sigma_at, peaks, pairs, *, ratio, grading, centred):
    """One face's refinement toward the anchors (positions along ``tangent``), in its own
    parameter, family and degree, with at most ``pairs`` collocation points."""
    degree = body.face_refinement(tag).degree
    family = body.family
    curve = body.face_curve(tag)  # the face's own curve, not a refined one
    sigma = estimate.parameter_of(curve, tangent)(sigma_at)
    flip = bool((curve.points([1.0])[0] - curve.points([0.0])[0]) @ tangent < 0)
    if flip:
        sigma = 1.0 - sigma

    @functools.cache
    def layout(elements):
        bounds = aligned_breakpoints(
            sigma, elements, ratio=ratio, grading=grading, centred=centred, peaks=peaks
        )
        marks = [] if centred else [bounds[np.argmin(np.abs(bounds - t))] for t in sigma]
        marks = np.unique([t for t in marks if 0.0 < t < 1.0])
        if flip:
            bounds, marks = (1.0 - bounds)[::-1], np.sort(1.0 - marks)
        return Refinement.explicit(bounds, degree=degree, c0_at=marks)

    def count(elements):
        refined = body.with_face_refinement(tag, layout(elements))
        return refined.face_segment(tag)[1].n_functions

    return _fitted_layout(family, degree, pairs, curve, layout, count, _marks_count(sigma, centred))


def remesh(
    simulation,
    anchors: np.ndarray,
    pairs: int,
    *,
    ratio: float = 4.0,
    grading: float = 0.15,
    centred: bool = False,
    edges: np.ndarray | None = None,
    edge_peak: float = 1.0,
    independent: bool | None = None,
):
    """The simulation with both contact faces re-meshed toward ``anchors``, <= ``pairs`` pairs.

    ``anchors`` are positions along the pair tangent. Each becomes a breakpoint where the
    basis is C0 (a collocation point on it for NURBS and Lagrange alike), or with
    ``centred`` the centre of an element. Node-to-node pairs (faces alike): elements are
    laid out in the upper face's parameter and carried to the lower face by position, so
    pairs still face each other. Faces that cannot face each other node to node (other
    families, degrees or pair counts; or a layout whose mean normal tilts the pair frame
    on curved faces) are each laid out on their own and paired by projection
    (:class:`~fretbem.contact.node_to_segment.NodeToSegmentPair`); ``independent`` forces
    one or the other. Returns a new Simulation (nothing assembled yet).
    """
    pair = simulation.pair
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        estimate.contact_segment(body, tag)  # each face one segment, or a clear error
    if independent is None:
        independent = isinstance(pair, NodeToSegmentPair)
        if not independent:
            matched = _matched(
                simulation, anchors, pairs, ratio, grading, centred, edges, edge_peak
            )
            try:
                matched.pair.pairing()
                return matched
            except ContactDiscretisationError:
                independent = True
    if not independent:
        return _matched(simulation, anchors, pairs, ratio, grading, centred, edges, edge_peak)
    tangent = estimate.pair_frame(pair)[1][0]
    edges = np.zeros(0) if edges is None else np.asarray(edges, float)
    peaks = np.concatenate([np.ones(np.size(anchors)), np.full(edges.size, edge_peak)])
    anchors = np.concatenate([np.asarray(anchors, float).ravel(), edges])
    faces = {}
    for label in ("upper", "lower"):
        body, tag = pair.side(label)
        refinement = _face_layout(
            body, tag, tangent, anchors, peaks, pairs, ratio=ratio, grading=grading,
            centred=centred,
        )  # fmt: skip
        faces[label] = body.with_face_refinement(tag, refinement)
    if isinstance(pair, NodeToSegmentPair):
        new_pair = attrs.evolve(pair, upper=faces["upper"], lower=faces["lower"])
    else:
        new_pair = NodeToSegmentPair(
            upper=faces["upper"],
            lower=faces["lower"],
            upper_tag=pair.upper_tag,
            lower_tag=pair.lower_tag,
        )
    return attrs.evolve(simulation, pair=new_pair)


def _size(curve) -> float:
    return float(np.abs(curve.control_points).max())


def mirror_symmetric(curve, tangent: np.ndarray) -> bool:
    """Whether ``curve`` is its own mirror image, traversed backwards, about the line through
    the origin normal to ``tangent`` (to :data:`SYMMETRY_TOLERANCE`): C(1 - s) = M C(s), so
    positions along ``tangent`` are mirrored x -> -x with the parameter s -> 1 - s."""
    points = getattr(curve, "control_points", None)
    weights, knots = getattr(curve, "weights", None), getattr(curve, "knots", None)
    if points is None or weights is None or knots is None or not points.size:
        return False
    t = np.asarray(tangent, float) / np.linalg.norm(tangent)
    mirrored = points[::-1] - 2.0 * np.outer(points[::-1] @ t, t)
    return bool(
        np.abs(mirrored - points).max() <= SYMMETRY_TOLERANCE * _size(curve)
        and np.abs(weights[::-1] - weights).max() <= SYMMETRY_TOLERANCE * np.abs(weights).max()
        and np.abs(knots[0] + knots[-1] - knots[::-1] - knots).max()
        <= SYMMETRY_TOLERANCE * (knots[-1] - knots[0])
    )


def point_image(curve, other) -> bool:
    """Whether ``curve`` is ``other``'s exact point image (x, y) -> (-x, -y), the same
    parameterisation: every coefficient equal, the control points negated."""
    return bool(
        type(curve) is type(other)
        and getattr(curve, "degree", None) == getattr(other, "degree", None)
        and hasattr(curve, "control_points")
        and np.array_equal(curve.knots, other.knots)
        and np.array_equal(curve.weights, other.weights)
        and np.array_equal(curve.control_points, -other.control_points)
    )


def symmetric_anchors(anchors: np.ndarray, peaks: np.ndarray, size: float) -> bool:
    """Whether positions ``anchors`` (with their ``peaks``) are their own mirror image
    x -> -x, to :data:`SYMMETRY_TOLERANCE` of ``size``."""
    anchors = np.asarray(anchors, float)
    order = np.argsort(anchors)
    x, peaks = anchors[order], np.asarray(peaks, float)[order]
    return bool(
        np.all(np.abs(x + x[::-1]) <= SYMMETRY_TOLERANCE * size)
        and np.array_equal(peaks, peaks[::-1])
    )


def _mirror_layout(refinement) -> bool:
    """Whether a face refinement's breakpoints and C0 marks are their own mirror exactly."""
    bounds, marks = refinement.breakpoints(), np.asarray(refinement.c0_at, float)
    # np.allclose(rtol=0) of finite values, without its broadcasting and special cases
    return bool(
        np.array_equal(bounds, _mirrored(bounds))
        and np.all(np.abs(marks - (1.0 - marks)[::-1]) <= SYMMETRY_TOLERANCE)
    )


#: what :func:`_faces` found, per upper face curve, lower face curve and tangent (weak in
#: the curves: the faces' own curves outlive the levels re-meshed on them)
_FACES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _faces(up_curve, low_curve, tangent: np.ndarray) -> tuple[bool, bool, bool]:
    """Whether the upper face runs against ``tangent`` (its layout flipped), whether both
    faces are their own mirror images (:func:`mirror_symmetric`) and whether the lower is
    the upper's point image (:func:`point_image`); kept per pair of curves and tangent."""
    by_lower = _FACES.setdefault(up_curve, weakref.WeakKeyDictionary())
    found = by_lower.setdefault(low_curve, {})
    key = tangent.tobytes()
    if key not in found:
        found[key] = (
            bool((up_curve.points([1.0])[0] - up_curve.points([0.0])[0]) @ tangent < 0),
            mirror_symmetric(up_curve, tangent) and mirror_symmetric(low_curve, tangent),
            point_image(low_curve, up_curve),
        )
    return found[key]


def _matched(simulation, anchors, pairs, ratio, grading, centred, edges, edge_peak):
    """Both faces laid out in the upper face's parameter, the lower carried by position."""
    pair = simulation.pair
    tangent = estimate.pair_frame(pair)[1][0]
    degree = pair.upper.face_refinement(pair.upper_tag).degree
    family = pair.upper.family
    # the faces' own curves (not the refined ones, whose knots would be kept)
    up_curve = pair.upper.face_curve(pair.upper_tag)
    low_curve = pair.lower.face_curve(pair.lower_tag)
    edges = np.zeros(0) if edges is None else np.asarray(edges, float)
    peaks = np.concatenate([np.ones(np.size(anchors)), np.full(edges.size, edge_peak)])
    anchors = np.concatenate([np.asarray(anchors, float).ravel(), edges])
    sigma = estimate.parameter_of(up_curve, tangent)(anchors)
    flip, mirrored, images = _faces(up_curve, low_curve, tangent)
    if flip:
        sigma = 1.0 - sigma
    symmetric = not centred and mirrored and symmetric_anchors(anchors, peaks, _size(up_curve))
    # similar faces of one material laid out alike: point images of each other to the last
    # bit, so that the lower body takes the upper's blocks and factors (fretbem.bem.images)
    alike = (
        symmetric
        and images
        and getattr(pair.upper, "material", None) == getattr(pair.lower, "material", None)
    )
    if symmetric:  # the anchors' parameters symmetric exactly, as their positions are
        order = np.argsort(sigma)
        sigma = sigma.copy()
        sigma[order] = 0.5 * (sigma[order] + 1.0 - sigma[order][::-1])

    @functools.cache
    def layout(elements):
        bounds = aligned_breakpoints(
            sigma, elements, ratio=ratio, grading=grading, centred=centred, peaks=peaks,
            symmetric=symmetric,
        )  # fmt: skip
        if flip:
            bounds = (1.0 - bounds)[::-1]
        if alike:  # mirrored exactly (the uniform layout and a flip are so to round-off)
            bounds = _mirrored(bounds)
        # the bounds are in the face's own parameter again: so are the anchors' marks
        targets = 1.0 - sigma if flip else sigma
        marks = [] if centred else [bounds[np.argmin(np.abs(bounds - t))] for t in targets]
        marks = np.unique([t for t in marks if 0.0 < t < 1.0])
        return Refinement.explicit(bounds, degree=degree, c0_at=marks)

    def count(elements):
        refined = pair.upper.with_face_refinement(pair.upper_tag, layout(elements))
        return refined.face_segment(pair.upper_tag)[1].n_functions

    def lower_of(upper):
        low_inverse = estimate.parameter_of(low_curve, tangent)
        bounds, marks = upper.breakpoints(), np.array(upper.c0_at)
        along = up_curve.points(bounds) @ tangent
        low_bounds = low_inverse(along)
        low_marks = low_inverse(up_curve.points(marks) @ tangent) if marks.size else marks
        order = np.argsort(low_bounds)
        low_bounds = low_bounds[order]
        low_bounds[0], low_bounds[-1] = 0.0, 1.0
        snap = [low_bounds[np.argmin(np.abs(low_bounds - t))] for t in low_marks]
        return Refinement.explicit(low_bounds, degree=degree, c0_at=snap)

    # the marks lie at the breakpoints nearest the anchors' parameters: with the layout
    # flipped back (flip) those are another face end's, so only its layouts say how many
    marks = None if flip else _marks_count(sigma, centred)
    upper_ref = _fitted_layout(family, degree, pairs, up_curve, layout, count, marks)
    if alike and _mirror_layout(upper_ref):
        # the lower face is the upper's point image, C_l(s) = -C_u(s), and the layout is
        # its own mirror: carried by position, each breakpoint s lands on 1 - (1 - s); taken
        # as it is, the two faces are point images to the last bit (their blocks shared,
        # fretbem.bem.images)
        lower_ref = upper_ref
    else:
        lower_ref = lower_of(upper_ref)
    upper = pair.upper.with_face_refinement(pair.upper_tag, upper_ref)
    lower = pair.lower.with_face_refinement(pair.lower_tag, lower_ref)
    return attrs.evolve(simulation, pair=attrs.evolve(pair, upper=upper, lower=lower))
