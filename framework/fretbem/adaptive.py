"""Adaptive contact meshes: collocation points on the contact edges and stick-slip boundaries.

A first solve of the whole history locates, at every step, the contact edges (where p falls
to zero like a square root) and the boundaries between stick and slip (where q has a
square-root cusp). The contact faces of both bodies are then re-meshed so that each of
these transition points is the centre of an element, elements are graded toward them, and
the history is solved again; levels repeat until the tractions change less than a
tolerance or the pair budget is spent. The last two levels give the error estimate
(:mod:`fretbem.estimate`). Why centres of elements: docs/explanation/adaptive.rst.
"""

from __future__ import annotations

import math
import time

import attrs
import numpy as np

from . import estimate
from .basis import Refinement
from .contact import SEPARATED

__all__ = [
    "AdaptiveError",
    "AdaptiveResult",
    "AdaptiveSettings",
    "Transitions",
    "aligned",
    "aligned_breakpoints",
    "edge_corrections",
    "knot_pressures",
    "pairs_for",
    "remesh",
    "run_adaptive",
    "transitions",
]

#: smallest transition spacing kept apart, as a fraction of the face length
MERGE = 2e-3
#: detected contact edges are moved outward by this fraction of the contact half-width: a
#: collocation point just inside the true edge sees the square root of the pressure (an edge
#: 0.05 % too far in costs 2 % of p0 at 61 pairs) while one just outside costs little
#: (0.2 % out: +0.6 %); measured on the reference scene, docs/explanation/adaptive.rst
EDGE_MARGIN = 1e-3


class AdaptiveError(ValueError):
    """Settings or a face the adaptive mode cannot work with."""


def _budget(instance, attribute, value) -> None:
    if isinstance(value, bool) or int(value) != value or value < 5:
        raise AdaptiveError(
            f"AdaptiveSettings.{attribute.name} must be a whole number of pairs >= 5, got {value!r}"
        )


@attrs.frozen
class AdaptiveSettings:
    """What the user asks of the adaptive mode: a tolerance or a pair budget.

    Attributes
    ----------
    tolerance : float
        Stop when the estimated error (max over steps of e_p max and e_q max, fractions of
        p0 and f p0) of two aligned levels is below this (default 2 %, the target for e_q).
    budget : int
        Most pairs in the candidate zone; the last level uses at most this many.
    first : int
        Pairs of the first, uniform level that finds the transitions.
    ratio : float
        Largest over smallest element of the graded levels (>= 1).
    grading : float
        Distance (fraction of the face's parameter) over which elements grow to full size.
    edge_peak : float
        Element density at contact edges relative to stick-slip boundaries (0, 1]: edges
        are graded less, see docs/explanation/adaptive.rst.
    edge_tolerance : float
        Re-solve at the budget once if an edge knot's point carries pressure that moves
        the edge by more than this fraction of the contact half-width.
    edge_iterations : int
        Most such re-solves (the first move from :func:`edge_corrections`, then secant
        steps on the knot point's pressure).
    max_levels : int
        Most aligned levels after the first.
    """

    tolerance: float = attrs.field(default=0.02, converter=float)
    budget: int = attrs.field(default=61, validator=_budget)
    first: int = attrs.field(default=31, validator=_budget)
    ratio: float = attrs.field(default=10.0, converter=float)
    max_levels: int = attrs.field(default=3, converter=int)
    grading: float = attrs.field(default=0.06, converter=float)
    edge_peak: float = attrs.field(default=0.5, converter=float)
    edge_tolerance: float = attrs.field(default=2e-4, converter=float)
    edge_iterations: int = attrs.field(default=3, converter=int)

    def __attrs_post_init__(self) -> None:
        if not (0.0 < self.tolerance < 1.0):
            raise AdaptiveError(
                f"AdaptiveSettings.tolerance is a fraction of p0, 0 < tolerance < 1; got "
                f"{self.tolerance!r} (e.g. 0.005 for 0.5 %)"
            )
        if not (0.0 < self.grading <= 1.0 and 0.0 < self.edge_peak <= 1.0):
            raise AdaptiveError(
                f"AdaptiveSettings.grading and edge_peak must lie in (0, 1], got "
                f"{self.grading!r} and {self.edge_peak!r}"
            )
        if not (self.ratio >= 1.0 and math.isfinite(self.ratio)):
            raise AdaptiveError(f"AdaptiveSettings.ratio must be >= 1, got {self.ratio!r}")
        if self.max_levels < 2:
            raise AdaptiveError(
                f"AdaptiveSettings.max_levels must be >= 2 (two aligned levels give the "
                f"estimate), got {self.max_levels!r}"
            )


# -- transitions ---------------------------------------------------------------------------
def _root_of_square(x: np.ndarray, values: np.ndarray, towards: float) -> float | None:
    """Zero of a quadratic fit of values^2 (a square-root fall to zero) nearest ``towards``."""
    if x.size < 2:
        return None
    # a square-root fall squared is quadratic (Hertz, exactly) and linear near its zero
    coefficients = np.polyfit(x, values**2, 2 if x.size >= 4 else 1)
    roots = np.roots(coefficients)
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
    for i in range(n - 1):
        a, b = i, i + 1
        if not ((stick[a] and slip[b]) or (slip[a] and stick[b])):
            continue
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
    along = estimate.positions(result)
    order = np.argsort(along)
    x = along[order]
    gap = float(np.min(np.diff(x)))
    friction = estimate.friction_of(result.simulation)
    edges: list[float] = []
    boundaries: list[float] = []
    for step in result.steps:
        p, q, states = step.pressure[order], step.shear[order], step.states[order]
        inside = states != SEPARATED
        if not inside.any():
            continue
        k = np.flatnonzero(inside)
        margin = EDGE_MARGIN * 0.5 * (x[k[-1]] - x[k[0]])
        for side in (-1, 1):
            edges.append(_edge(x, p, inside, side, gap) + side * margin)
        boundaries += _stick_boundaries(x, p, q, states, friction)
    tolerance = MERGE * (x[-1] - x[0])
    return Transitions(_merge(edges, tolerance), _merge(boundaries, tolerance))


#: the pressure at a collocation point on a C0 knot a distance d inside the discrete contact
#: edge is about KNOT_SLOPE * A * d / sqrt(h) (A: amplitude of p = A sqrt(edge - x), h: the
#: element size there); measured 1.4 to 1.9 on the reference scene at 31 to 61 pairs
KNOT_SLOPE = 1.6


def knot_pressures(result, edges: np.ndarray) -> np.ndarray:
    """Largest pressure over the steps at the point on each edge knot (0 if separated)."""
    along = estimate.positions(result)
    order = np.argsort(along)
    x = along[order]
    out = np.zeros(len(edges))
    for j, edge in enumerate(edges):
        k = int(np.argmin(np.abs(x - edge)))
        if abs(x[k] - edge) > 1e-3 * np.min(np.diff(x)):
            continue
        for step in result.steps:
            if step.states[order][k] != SEPARATED:
                out[j] = max(out[j], float(step.pressure[order][k]))
    return out


def edge_corrections(result, edges: np.ndarray) -> np.ndarray:
    """Outward moves of the edge knots that bring their points' pressure to zero.

    A point on a C0 knot inside the discrete edge carries pressure, growing linearly with
    the distance (:data:`KNOT_SLOPE`); one outside is separated and gets no move. Returns
    signed moves along the face, one per edge (step with the largest pressure there).
    """
    along = estimate.positions(result)
    order = np.argsort(along)
    x = along[order]
    moves = np.zeros(len(edges))
    for j, edge in enumerate(edges):
        k = int(np.argmin(np.abs(x - edge)))
        if abs(x[k] - edge) > 1e-3 * np.min(np.diff(x)):  # no point on this edge
            continue
        side = 1 if edge > 0.5 * (x[0] + x[-1]) else -1
        inner = k - side
        if not (0 <= inner < x.size and 0 <= inner - 2 * side < x.size):
            continue
        h = abs(x[k] - x[inner])
        for step in result.steps:
            p = step.pressure[order]
            if p[k] <= 0.0 or step.states[order][k] == SEPARATED:
                continue
            near = [inner, inner - side, inner - 2 * side]
            slope = abs(np.polyfit(x[near], p[near] ** 2, 1)[0])
            amplitude = math.sqrt(slope) if slope > 0 else 0.0
            if amplitude > 0.0:
                move = p[k] * math.sqrt(h) / (KNOT_SLOPE * amplitude)
                moves[j] = side * max(abs(moves[j]), move)
    return moves


# -- aligned meshes -----------------------------------------------------------------------
def aligned_breakpoints(
    anchors: np.ndarray,
    elements: int,
    *,
    ratio: float = 4.0,
    grading: float = 0.15,
    centred: bool = False,
    peaks: np.ndarray | None = None,
) -> np.ndarray:
    """Breakpoints in [0, 1]: ``elements`` elements, graded toward ``anchors``.

    Each anchor is a breakpoint, or with ``centred`` the centre of an element. Element
    density falls linearly with the distance to an anchor, from ``peaks`` (default 1) at it
    to 1 / ``ratio`` at ``grading`` (fraction of [0, 1]) and beyond; the gaps between
    anchors get whole numbers of elements that equidistribute it.
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
    slope = (ratio - 1.0) / grading
    grid = np.linspace(0.0, 1.0, 8001)
    distance = np.abs(grid[:, None] - anchors[None, :])
    rho = np.maximum(1.0 / ratio, np.max(peaks / (1.0 + slope * distance), axis=1))
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (rho[1:] + rho[:-1]) * np.diff(grid))])
    spacing = np.diff(np.concatenate([[-anchors[0]], anchors, [2.0 - anchors[-1]]]))
    room = 0.3 * np.minimum(spacing[:-1], spacing[1:])

    def layout(h):
        half = np.minimum(0.5 * h, room) if centred else np.zeros(m)
        starts = np.concatenate([[0.0], anchors + half])
        ends = np.concatenate([anchors - half, [1.0]])
        work = (np.interp(ends, grid, cumulative) - np.interp(starts, grid, cumulative)) / h
        return half, starts, ends, work

    target = elements - fixed
    lo_h, hi_h = 1e-7, 2.0
    for _ in range(80):
        h = math.sqrt(lo_h * hi_h)
        total = np.maximum(layout(h)[3], 1.0).sum()
        lo_h, hi_h = (h, hi_h) if total > target else (lo_h, h)
    _, starts, ends, work = layout(math.sqrt(lo_h * hi_h))
    counts = np.maximum(np.floor(work), 1).astype(int)
    while counts.sum() < target:
        counts[np.argmax(work - counts)] += 1
    while counts.sum() > target:
        spare = np.where(counts > 1, counts - work, -np.inf)
        counts[np.argmax(spare)] -= 1
    points = [np.array([0.0])]
    for a, b, n in zip(starts, ends, counts, strict=True):
        ca, cb = np.interp([a, b], grid, cumulative)
        inner = np.interp(np.linspace(ca, cb, n + 1), cumulative, grid)
        inner[0], inner[-1] = a, b
        points.append(inner)
    out = np.unique(np.concatenate(points))
    out[0], out[-1] = 0.0, 1.0
    return out


def pairs_for(family, elements: int, degree: int | None = None) -> int:
    """Collocation points (pairs) the family puts on a face of ``elements`` elements."""
    from .geometry.nurbs import NurbsCurve

    line = NurbsCurve.line([0, 0], [1, 0], degree=1)
    return family.discretise(line, Refinement(elements=elements, degree=degree)).n_functions


def elements_for(family, pairs: int, degree: int | None = None) -> int:
    """Most elements whose face has at most ``pairs`` collocation points."""
    a, b = pairs_for(family, 4, degree), pairs_for(family, 8, degree)
    per, extra = (b - a) / 4, a - 4 * (b - a) / 4
    return max(1, math.floor((pairs - extra) / per))


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
):
    """The simulation with both contact faces re-meshed toward ``anchors``, <= ``pairs`` pairs.

    ``anchors`` are positions along the pair tangent. Each becomes a breakpoint where the
    basis is C0 (a collocation point on it for NURBS and Lagrange alike), or with
    ``centred`` the centre of an element. Elements are laid out in the upper face's
    parameter and carried to the lower face by position, so pairs still face each other.
    Returns a new Simulation (nothing assembled yet).
    """
    pair = simulation.pair
    tangent = estimate.pair_frame(pair)[1][0]
    up_index, _ = estimate.contact_segment(pair.upper, pair.upper_tag)
    low_index, _ = estimate.contact_segment(pair.lower, pair.lower_tag)
    degree = pair.upper.refinement.get(pair.upper_tag, Refinement()).degree
    family = pair.upper.family
    # the segments' own curves (not the refined ones, whose knots would be kept)
    up_curve = pair.upper.boundary.segments[up_index].curve
    low_curve = pair.lower.boundary.segments[low_index].curve
    edges = np.zeros(0) if edges is None else np.asarray(edges, float)
    peaks = np.concatenate([np.ones(np.size(anchors)), np.full(edges.size, edge_peak)])
    anchors = np.concatenate([np.asarray(anchors, float).ravel(), edges])
    sigma = estimate.parameter_of(up_curve, tangent)(anchors)
    flip = bool((up_curve.points([1.0])[0] - up_curve.points([0.0])[0]) @ tangent < 0)
    if flip:
        sigma = 1.0 - sigma
    low_inverse = estimate.parameter_of(low_curve, tangent)

    def build(elements):
        bounds = aligned_breakpoints(
            sigma, elements, ratio=ratio, grading=grading, centred=centred, peaks=peaks
        )
        if flip:
            bounds = (1.0 - bounds)[::-1]
        marks = [] if centred else [bounds[np.argmin(np.abs(bounds - t))] for t in sigma]
        marks = np.unique([t for t in marks if 0.0 < t < 1.0])
        upper = Refinement.explicit(bounds, degree=degree, c0_at=marks)
        along = up_curve.points(bounds) @ tangent
        low_bounds = low_inverse(along)
        low_marks = low_inverse(up_curve.points(marks) @ tangent) if marks.size else marks
        order = np.argsort(low_bounds)
        low_bounds = low_bounds[order]
        low_bounds[0], low_bounds[-1] = 0.0, 1.0
        snap = [low_bounds[np.argmin(np.abs(low_bounds - t))] for t in low_marks]
        lower = Refinement.explicit(low_bounds, degree=degree, c0_at=snap)
        return upper, lower, family.discretise(up_curve, upper).n_functions

    elements = elements_for(family, pairs, degree)
    while True:
        upper_ref, lower_ref, count = build(elements)
        if count <= pairs or elements <= 1:
            break
        per = (pairs_for(family, 8, degree) - pairs_for(family, 4, degree)) / 4
        elements -= max(1, math.ceil((count - pairs) / per))
    upper = attrs.evolve(
        pair.upper, refinement={**pair.upper.refinement, pair.upper_tag: upper_ref}
    )
    lower = attrs.evolve(
        pair.lower, refinement={**pair.lower.refinement, pair.lower_tag: lower_ref}
    )
    return attrs.evolve(simulation, pair=attrs.evolve(pair, upper=upper, lower=lower))


# -- the loop -------------------------------------------------------------------------------
@attrs.frozen(eq=False)
class AdaptiveResult:
    """Every level's result, the transitions found, the estimate and the time of it all.

    Attributes
    ----------
    levels : tuple of SimulationResult
        First (uniform) level first; the last is the answer.
    transitions : tuple of Transitions
        Transitions used to build each aligned level.
    estimate : dict
        Per step name, the estimated error of the last level (keys of StepResult.errors).
    seconds : float
        Wall time of all levels (assembly, condensation and solves).
    """

    levels: tuple
    transitions: tuple
    estimate: dict
    seconds: float

    @property
    def result(self):
        """The finest level's SimulationResult."""
        return self.levels[-1]

    def table(self) -> str:
        """Per step: the finest level's errors (if a closed form exists) beside the estimate."""

        def pct(value):
            return "   n/a" if value is None else f"{100 * value:6.3f}"

        lines = [
            "levels (pairs): "
            + ", ".join(str(r.steps[0].x.size) for r in self.levels)
            + f"; all levels {self.seconds:.3f} s",
            "step   e_p max%  est     e_q max%  est     e_p L2%   est     e_q L2%   est",
        ]
        for step in self.result.steps:
            true, est = step.errors or {}, self.estimate[step.name]
            cells = [
                f"{pct(true.get(k))}  {pct(est[k])}"
                for k in ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
            ]
            lines.append(f"{step.name:<5s} " + "  ".join(cells))
        return "\n".join(lines)

    def summary(self) -> dict:
        """Levels, transitions, timings and the per-step estimate, for summary.json."""
        return {
            "levels": [int(r.steps[0].x.size) for r in self.levels],
            "transitions": [t.all.tolist() for t in self.transitions],
            "seconds": self.seconds,
            "estimate": {name: dict(e) for name, e in self.estimate.items()},
        }

    @property
    def estimated_max(self) -> float:
        """Largest estimated max error over steps, p and q."""
        return max(max(e["e_p_max"], e["e_q_max"]) for e in self.estimate.values())


def _solve(simulation):
    from .simulation import run

    return run(simulation)


def _level_pairs(settings: AdaptiveSettings, family, degree) -> list[int]:
    """Pair counts of the aligned levels: ``first`` doubled while below the budget, then it.

    A budget within 20 % of ``first`` gets half the budget as its first aligned level (two
    counts that close cannot be told apart by the estimate).
    """

    def fit(pairs: int) -> int:
        return pairs_for(family, elements_for(family, pairs, degree), degree)

    top = fit(settings.budget)
    counts, n = [], settings.first
    while fit(n) < top and len(counts) < settings.max_levels - 1:
        counts.append(fit(n))
        n = 2 * n - 1
    if not counts or counts[0] > 0.8 * top:
        counts = [fit((top + 1) // 2)]
    return [*counts, top]


def _half_width(result) -> float:
    """Half-width of the widest contact of the history, along the face."""
    along = estimate.positions(result)
    widths = [np.ptp(along[s.states != SEPARATED]) for s in result.steps]
    return 0.5 * max(widths)


def aligned(simulation, found: Transitions, pairs: int, settings: AdaptiveSettings):
    """The simulation re-meshed for ``found`` with at most ``pairs`` pairs (not solved)."""
    return remesh(
        simulation,
        found.boundaries,
        pairs,
        ratio=settings.ratio,
        grading=settings.grading,
        edges=found.edges,
        edge_peak=settings.edge_peak,
    )


def run_adaptive(simulation, settings: AdaptiveSettings | None = None) -> AdaptiveResult:
    """Solve, find the transitions, re-mesh aligned, and re-solve until tolerance or budget.

    Levels: a uniform first level of ``settings.first`` pairs, then aligned levels of about
    doubling pair counts up to the budget (the transitions re-found from each level); the
    run stops early when the estimate from the last two aligned levels is below the
    tolerance. The estimate always comes from two aligned levels.
    """
    settings = settings or AdaptiveSettings()
    start = time.perf_counter()
    pair = simulation.pair
    family = pair.upper.family
    degree = pair.upper.refinement.get(pair.upper_tag, Refinement()).degree
    counts = _level_pairs(settings, family, degree)
    first = remesh(simulation, np.array([]), settings.first, ratio=1.0)
    levels = [_solve(first)]
    found = []
    estimated: dict = {}
    for k, pairs in enumerate(counts):
        latest = transitions(levels[-1])
        if found:  # edges from the uniform level: an aligned level biases their fit inward
            latest = Transitions(found[0].edges, latest.boundaries)
        found.append(latest)
        levels.append(_solve(aligned(simulation, found[-1], pairs, settings)))
        if k >= 1:
            estimated = estimate.estimate_errors(levels[-2], levels[-1])
            worst = max(max(e["e_p_max"], e["e_q_max"]) for e in estimated.values())
            if worst < settings.tolerance:
                break
    coarse, history, pairs = levels[-2], [], levels[-1].steps[0].x.size
    for _ in range(settings.edge_iterations):
        edges = found[-1].edges
        pressure = knot_pressures(levels[-1], edges)
        history.append((edges, pressure))
        if len(history) == 1:
            moves = edge_corrections(levels[-1], edges)
        else:  # secant on the knot point's pressure, which is linear in the edge position
            (e0, p0), (e1, p1) = history[-2], history[-1]
            de = np.where(e1 != e0, e1 - e0, np.inf)
            slope = (p1 - p0) / de
            ok = (p1 > 0) & (np.abs(slope) > 0)
            moves = np.where(ok, -p1 / np.where(ok, slope, 1.0), 0.0)
            # never more than the first move, never inward
            limit = np.abs(history[0][0] - history[1][0]) + 1e-300
            outward = np.sign(edges - edges.mean())
            moves = outward * np.clip(moves * outward, 0.0, 2.0 * limit)
        if not np.any(np.abs(moves) > settings.edge_tolerance * _half_width(levels[-1])):
            break
        found.append(Transitions(edges + moves, found[-1].boundaries))
        levels.append(_solve(aligned(simulation, found[-1], pairs, settings)))
        estimated = estimate.estimate_errors(coarse, levels[-1])
    if not estimated:
        estimated = estimate.estimate_errors(levels[-2], levels[-1])
    return AdaptiveResult(
        levels=tuple(levels),
        transitions=tuple(found),
        estimate=estimated,
        seconds=time.perf_counter() - start,
    )
