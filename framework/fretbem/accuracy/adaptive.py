"""Adaptive contact meshes: collocation points on the contact edges and stick-slip boundaries.

A first, uniform solve of the whole history locates the contact edges (p falls to zero like
a square root) and the stick-slip boundaries (q has a square-root cusp) of every step. The
contact faces are re-meshed with a C0 knot, hence a collocation point, on each transition
(:mod:`fretbem.accuracy.remesh`), the knots are moved onto the level's own discrete
transitions (:mod:`fretbem.accuracy.knots`), and aligned levels repeat up to the pair budget
or until the estimate from the last two (:mod:`fretbem.accuracy.estimate`) is below a tolerance.
Why: docs/explanation/adaptive.rst.
"""

from __future__ import annotations

import math
import time

import attrs
import numpy as np

from fretbem.contact.pairs import NodeToNodePair
from fretbem.simulation import run
from fretbem.solvers.warm_start import WarmStart
from fretbem.validators import count_field, number_field

from . import estimate
from .knots import (
    FALLBACK_REACH,
    SEPARATED,
    Transitions,
    fit_transitions,
    knot_moves,
    knot_pressures,
    knot_spacings,
    refound,
    transitions,
)
from .remesh import (
    MERGE,
    AdaptiveError,
    aligned_breakpoints,
    elements_for,
    knots_for,
    mirror_symmetric,
    pairs_for,
    remesh,
)

__all__ = [
    "AdaptiveError",
    "AdaptiveResult",
    "AdaptiveSettings",
    "Transitions",
    "aligned",
    "aligned_breakpoints",
    "elements_for",
    "fit_transitions",
    "knot_moves",
    "knot_pressures",
    "knots_for",
    "own_transitions",
    "pairs_for",
    "remesh",
    "run_adaptive",
    "transitions",
]


def _pairs(fix: str) -> attrs.Converter:
    return count_field(f"{fix} (pairs)", low=5, error=AdaptiveError)


def _number(what: str, fix: str, **bounds) -> attrs.Converter:
    return number_field(what, fix, error=AdaptiveError, **bounds)


#: (ratio, edge_peak) by whether the family is interpolatory (C0 at every element boundary:
#: quadratic Lagrange) or smooth (NURBS); measured on the reference scene, budgets 31 to 61:
#: Lagrange needs dense edges (edge_peak 0.5: e_p 1.3 %, 1.0 with ratio 20: 0.7 to 1.0 %),
#: NURBS points that close to the edge see the finite bodies' edge (edge_peak 1.0: 2.3 %)
FAMILY_GRADING = {False: (10.0, 0.5), True: (20.0, 1.0)}


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
    ratio : float or None
        Largest over smallest element of the graded levels (>= 1); None: the family's
        (:data:`FAMILY_GRADING`).
    grading : float
        Distance (fraction of the face's parameter) over which elements grow to full size.
    edge_peak : float or None
        Element density at contact edges relative to stick-slip boundaries (0, 1]; None:
        the family's (:data:`FAMILY_GRADING`).
    edge_tolerance : float
        A knot is settled when it would move by less than this fraction of the spacing of
        the points next to it (a fraction of the contact half-width did not shrink with the
        elements: settled knots at 121 pairs were further off, in elements, than at 61).
    edge_iterations : int
        Most re-solves that move the knots of the last level onto its own transitions
        (:func:`settle`).
    coarse_iterations : int
        The same for the first aligned level (it hands on its transitions and its error).
    coarse_tolerance : float
        The first aligned level is settled when no knot would move by more than this
        fraction of the contact half-width (with ``coarse_iterations`` = 2: a zone of 2 a
        leaves c' 6 % of a off after the uniform level and its estimate at 2.6 % at 61
        pairs, 0.6 % with a second pass; on the reference scene the second pass made e_p
        at budget 36 1.19 % and the q estimate up to 4 times too large at 47 to 55, so the
        default is one pass).
    max_levels : int
        Most aligned levels after the first (4: budgets above 121 get a 121-pair level
        before the last, so the estimate carries a pair ratio of about 2; from 61 straight
        to 241 it read 0.15 to 0.65 of the error, now 2 to 4 times it).
    """

    tolerance: float = attrs.field(
        default=0.02, converter=_number("a fraction of p0", "give e.g. 0.02 for 2 %")
    )
    budget: int = attrs.field(default=61, converter=_pairs("give e.g. 61"))
    first: int = attrs.field(default=31, converter=_pairs("give e.g. 31"))
    ratio: float | None = attrs.field(
        default=None,
        converter=_number(
            "largest over smallest element", "give e.g. 10, or None for the family's", none=True
        ),
    )
    max_levels: int = attrs.field(
        default=4,
        converter=count_field(
            "give e.g. 4 (two aligned levels give the estimate)", low=2, error=AdaptiveError
        ),
    )
    grading: float = attrs.field(
        default=0.06, converter=_number("a fraction of the face's parameter", "give e.g. 0.06")
    )
    edge_peak: float | None = attrs.field(
        default=None,
        converter=_number(
            "a relative element density", "give e.g. 1.0, or None for the family's", none=True
        ),
    )
    edge_tolerance: float = attrs.field(
        default=0.03,
        converter=_number(
            "a fraction of the point spacing", "give e.g. 0.03", low=0.0, low_open=True
        ),
    )
    edge_iterations: int = attrs.field(
        default=4, converter=count_field("give e.g. 4", low=0, error=AdaptiveError)
    )
    coarse_iterations: int = attrs.field(
        default=1, converter=count_field("give e.g. 1", low=0, error=AdaptiveError)
    )
    coarse_tolerance: float = attrs.field(
        default=0.01,
        converter=_number(
            "a fraction of the contact half-width", "give e.g. 0.01", low=0.0, low_open=True
        ),
    )

    def for_family(self, family) -> AdaptiveSettings:
        """These settings with ``ratio`` and ``edge_peak`` filled in for a basis family."""
        ratio, peak = FAMILY_GRADING[bool(getattr(family, "interpolatory", False))]
        return attrs.evolve(
            self,
            ratio=ratio if self.ratio is None else self.ratio,
            edge_peak=peak if self.edge_peak is None else self.edge_peak,
        )

    def __attrs_post_init__(self) -> None:
        if not (0.0 < self.tolerance < 1.0):
            raise AdaptiveError(
                f"AdaptiveSettings.tolerance is a fraction of p0, 0 < tolerance < 1; got "
                f"{self.tolerance!r} (e.g. 0.005 for 0.5 %)"
            )
        peak = 1.0 if self.edge_peak is None else self.edge_peak
        if not (0.0 < self.grading <= 1.0 and 0.0 < peak <= 1.0):
            raise AdaptiveError(
                f"AdaptiveSettings.grading and edge_peak must lie in (0, 1], got "
                f"{self.grading!r} and {self.edge_peak!r}"
            )
        if self.ratio is not None and not (self.ratio >= 1.0 and math.isfinite(self.ratio)):
            raise AdaptiveError(f"AdaptiveSettings.ratio must be >= 1, got {self.ratio!r}")
        if self.max_levels < 2:
            raise AdaptiveError(
                f"AdaptiveSettings.max_levels must be >= 2 (two aligned levels give the "
                f"estimate), got {self.max_levels!r}"
            )


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
    notes : tuple of str
        Where the estimate does not cover the error (transitions merged to fit the budget,
        knots not settled); empty when it does.
    """

    levels: tuple
    transitions: tuple
    estimate: dict
    seconds: float
    notes: tuple = ()

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
            "notes": list(self.notes),
        }

    @property
    def estimated_max(self) -> float:
        """Largest estimated max error over steps, p and q."""
        return max(max(e["e_p_max"], e["e_q_max"]) for e in self.estimate.values())


def _solve(simulation, after=None, knots=None):
    """Run a level; ``after`` (the level solved before it, or None) gives each increment's
    Newton start (:class:`~fretbem.solvers.warm_start.WarmStart`): the same unknowns to the
    solver's tolerance, in fewer iterations. ``knots`` (positions along the pair tangent of
    the level's C0 knots) say where the start's pattern changes when a knot lies on one of
    ``after``'s pairs (node-to-node pairs, which share one frame)."""
    if after is None:
        return run(simulation)
    points = None
    if knots is not None and isinstance(simulation.pair, NodeToNodePair):
        points = np.outer(np.asarray(knots, float), estimate.pair_frame(simulation.pair)[1][0])
    return run(simulation, warm=WarmStart.of(after, points))


#: a transition of a settled level is carried onto a knot closer than this many knot point
#: spacings (the knot stands for it); a farther one is a transition of its own. Two spacings
#: folded the rig's step E stick-slip boundary, 0.0085 mm from step A's knot, into it at
#: every level: no knot, and q 0.20 % off the converged solution at 121 pairs, 0.64 % at
#: 161 to 241; half a spacing gives it a knot (0.20, 0.18, 0.07 %) and leaves the reference
#: scene's levels as they were (docs/explanation/adaptive.rst, "Limits")
HAND_ON_REACH = 0.5

#: the same for a level coarser than the uniform first one (the first aligned level of a
#: budget below 61), which locates its transitions worse than the first level did (half a
#: spacing handed its misplaced ones on as new transitions: the reference scene at budget
#: 51, q 0.31 -> 0.55 %), and for faces paired by projection, whose knots lie on each
#: face's own layout, off the pair points (half a spacing: the mixed faces at 83 and 101
#: pairs, q 0.32 -> 0.62 % and 0.21 -> 0.45 %)
COARSE_HAND_ON_REACH = 2.0


def _level_pairs(settings: AdaptiveSettings, family, degree) -> list[int]:
    """Pair counts of the aligned levels: ``first`` doubled while below the budget, then it.

    A budget below twice ``first`` gets half the budget as its first aligned level: the
    estimate scales the coarse level's error by the pair ratio, best known near 2.
    """

    def fit(pairs: int) -> int:
        return pairs_for(family, elements_for(family, pairs, degree), degree)

    top = fit(settings.budget)
    counts, n = [], settings.first
    while fit(n) < top and len(counts) < settings.max_levels - 1:
        counts.append(fit(n))
        n = 2 * n - 1
    if not counts or counts[0] > 0.55 * top:
        counts = [fit((top + 1) // 2)]
    return [*counts, top]


def _half_width(result) -> float:
    """Half-width of the widest contact of the history, along the face."""
    along = estimate.positions(result)
    widths = [np.ptp(along[s.states != SEPARATED]) for s in result.steps]
    return 0.5 * max(widths)


def aligned(simulation, found: Transitions, pairs: int, settings: AdaptiveSettings):
    """The simulation re-meshed for ``found`` with at most ``pairs`` pairs (not solved)."""
    settings = settings.for_family(simulation.pair.upper.family)
    return remesh(
        simulation,
        found.boundaries,
        pairs,
        ratio=settings.ratio,
        grading=settings.grading,
        edges=found.edges,
        edge_peak=settings.edge_peak,
    )


#: inward knot moves (from a gap or a slip increment) are damped by this factor until the
#: knot's transition is bracketed: a knot inside its transition costs a square root of the
#: distance, one outside a power 1.5 (docs/explanation/adaptive.rst)
INWARD_DAMPING = 1.0

#: most a knot moves in one re-solve, as a fraction of the contact half-width: the uniform
#: first level finds the transitions within 1.5 % of a (6 % with a zone of 2 a), while a
#: coarse aligned level's signals can send a knot 10 % of a off, onto another transition
MAX_MOVE = 0.03


def _next_positions(positions, moves, history) -> np.ndarray:
    """Next position of every knot: the move (inward ones damped) until the knot's zero of
    move(position) is bracketed by two tried positions, then regula falsi inside the bracket."""
    out = positions + moves
    for i, (e, m) in enumerate(zip(positions, moves, strict=True)):
        tried = [(h[0][i], h[1][i]) for h in history] + [(e, m)]
        plus = [t for t in tried if t[1] > 0]
        minus = [t for t in tried if t[1] < 0]
        if plus and minus:  # the knot wants +: its zero lies above; pick the closest pair
            lo = max(plus, key=lambda t: t[0])
            hi = min(minus, key=lambda t: t[0])
            if lo[0] < hi[0]:
                out[i] = lo[0] - lo[1] * (hi[0] - lo[0]) / (hi[1] - lo[1])
                continue
        inward = np.sign(m) != np.sign(e)
        out[i] = e + (INWARD_DAMPING * m if inward else m)
    return _keep_apart(positions, out)


def _keep_apart(positions: np.ndarray, after: np.ndarray) -> np.ndarray:
    """``after`` with no knot moved past the middle of the gap to its neighbour: a knot that
    crossed another would leave a transition without a knot."""
    order = np.argsort(positions)
    ordered = positions[order]
    middles = 0.5 * (ordered[1:] + ordered[:-1])
    lo = np.concatenate([[-np.inf], middles])
    hi = np.concatenate([middles, [np.inf]])
    out = after.copy()
    out[order] = np.clip(after[order], lo, hi)
    return out


#: weight of a knot that still has to move outward (its point inside the transition, where
#: the error is a square root of the distance) against one that has to move inward
INSIDE_WEIGHT = 2.0


def _residual(
    positions: np.ndarray, moves: np.ndarray, scale: np.ndarray, crowded: bool = False
) -> float:
    """How far a level's knots are from settled: the largest move over ``scale`` (each
    knot's point spacing), outward moves (knot point inside its transition) weighted by
    :data:`INSIDE_WEIGHT`, over the knots free to make their move. A knot whose move goes
    past the middle of the gap to its neighbour (:func:`_keep_apart` stops it there) is
    crowded against another's transition and cannot settle on this level: counted, it
    set the residual of every re-solve of steel on aluminium at 51 pairs (5 to 31
    spacings), so the first placement was kept (q 3.6 % of f p0 away from the transitions
    against 0.74 to 0.88 % for the re-solves; docs/explanation/adaptive.rst, "Limits").
    With ``crowded`` every knot counts (what the run's caution reports)."""
    free = np.abs(_keep_apart(positions, positions + moves) - positions) >= np.abs(moves) * (
        1.0 - 1e-9
    )
    if crowded:
        free = np.ones(moves.size, bool)
    if not free.any():
        return 0.0
    centre = 0.5 * (positions.min() + positions.max())
    outward = np.sign(moves) == np.sign(positions - centre)
    weighted = np.abs(moves) / scale * np.where(outward, INSIDE_WEIGHT, 1.0)
    return float(np.max(weighted[free]))


#: the knots of a mirrored level stay mirrored while each pair's common move (what the
#: mirror keeps them from, :func:`settle`) is within this share of the settle tolerance, so
#: that the mirrored knots can settle by the same test as free ones
SYMMETRY_SHARE = 0.5


def symmetric_faces(simulation) -> bool:
    """Whether both contact faces are their own mirror images about the normal through the
    origin (positions x -> -x along the pair tangent; node-to-node pairs): aligned levels
    with mirrored knots are then mirror-symmetric, and similar faces point images of each
    other (:func:`fretbem.accuracy.remesh.remesh`), whose blocks the assembly shares
    (:mod:`fretbem.bem.images`, :mod:`fretbem.bem.mirror`)."""
    pair = simulation.pair
    if not isinstance(pair, NodeToNodePair):
        return False
    tangent = estimate.pair_frame(pair)[1][0]
    return all(
        mirror_symmetric(body.face_curve(tag), tangent)
        for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag))
    )


def _odd_part(values: np.ndarray) -> np.ndarray:
    """The part of sorted mirrored values that is odd under x -> -x (their mirror image
    negated and reversed averaged in): exactly mirrored, a middle one 0."""
    return 0.5 * (values - values[::-1])


def _merge_distance(simulation) -> float:
    """The layout's merge distance: :data:`~fretbem.accuracy.remesh.MERGE` of the extent of
    the contact pairs along the face."""
    points, tangents = estimate.pair_frame(simulation.pair)
    return MERGE * float(np.ptp(points @ tangents[0]))


def symmetrised(found: Transitions, apart: float) -> Transitions | None:
    """``found`` mirrored exactly about x = 0 if each edge and each boundary has a mirror
    image of its kind within ``apart`` (the layout's merge distance: closer transitions
    share an anchor), else None."""
    out = []
    for values in (found.edges, found.boundaries):
        values = np.sort(np.asarray(values, float))
        if values.size and np.abs(values + values[::-1]).max() > apart:
            return None
        out.append(_odd_part(values))
    return Transitions(*out)


def settle(
    simulation,
    found: Transitions,
    pairs: int,
    settings: AdaptiveSettings,
    iterations: int,
    tolerance: float | None = None,
    relative: bool = True,
    reach: float | None = None,
    after=None,
    symmetric: bool = False,
):
    """Solve an aligned level and move its knots onto its own discrete transitions.

    Returns the solved levels and the transitions of each, the settled level (the one whose
    knots would move least, :func:`_residual`) last, that level's residual with its
    crowded knots counted, and whether the knots stayed mirrored. With ``symmetric`` (a
    face pair that is its own mirror image, :func:`symmetric_faces`) the knots are
    mirrored about the middle (:func:`symmetrised`) and move in mirrored pairs while the
    level's transitions are mirrored too (:data:`SYMMETRY_SHARE`); from the first re-solve
    where they are not, each knot moves on its own. ``found`` is
    first cut to the knots the level can place (:func:`fit_transitions`). Stops when no knot
    would move by more than ``tolerance`` (default ``settings.edge_tolerance``) of its point
    spacing (``relative``) or of the contact half-width, or after ``iterations`` re-solves.
    ``after`` (a level solved before, or None) warm-starts the first solve; each re-solve
    starts from the one before it (:func:`_solve`).
    """
    tolerance = settings.edge_tolerance if tolerance is None else tolerance
    pair = simulation.pair
    degree = pair.upper.face_refinement(pair.upper_tag).degree
    found = fit_transitions(found, knots_for(pair.upper.family, pairs, degree))
    if symmetric:
        mirrored = symmetrised(found, _merge_distance(simulation))
        symmetric = mirrored is not None
        found = mirrored if symmetric else found
    levels = [_solve(aligned(simulation, found, pairs, settings), after, found.all)]
    used, history, residual, everything = [found], [], [], []
    for k in range(iterations + 1):
        edge_moves, boundary_moves = knot_moves(levels[-1], used[-1], reach)
        moves = np.concatenate([edge_moves, boundary_moves])
        positions = np.concatenate([used[-1].edges, used[-1].boundaries])
        scale = knot_spacings(levels[-1], used[-1]) if relative else _half_width(levels[-1])
        residual.append(_residual(positions, moves, scale))
        everything.append(_residual(positions, moves, scale, crowded=True))
        if residual[-1] <= tolerance or k == iterations:
            break
        n = used[-1].edges.size
        if symmetric:
            mirrored = np.concatenate([_odd_part(edge_moves), _odd_part(boundary_moves)])
            # the knots stay mirrored while what the mirror keeps them from (each pair's
            # common move) would count as settled on its own, with room to spare; the
            # history then holds the mirrored moves (regula falsi on mirrored pairs)
            common = _residual(positions, moves - mirrored, scale)
            symmetric = common <= SYMMETRY_SHARE * tolerance
            moves = mirrored if symmetric else moves
        cap = MAX_MOVE * _half_width(levels[-1])
        after = _next_positions(positions, np.clip(moves, -cap, cap), history)
        history.append((positions, moves))
        if symmetric:
            after = np.concatenate([_odd_part(after[:n]), _odd_part(after[n:])])
        used.append(Transitions(after[:n], after[n:]))
        level = aligned(simulation, used[-1], pairs, settings)
        levels.append(_solve(level, levels[-1], used[-1].all))
    best = int(np.argmin(residual))
    order = [*(i for i in range(len(levels)) if i != best), best]
    return [levels[i] for i in order], [used[i] for i in order], everything[best], symmetric


def own_transitions(settled: Transitions, handed: Transitions, apart: float) -> Transitions | None:
    """``settled`` with the transitions of ``handed`` (a settled level's own, :func:`refound`)
    that lie farther than ``apart`` (the layout's merge distance) from every knot of their
    own kind; None if there are none.

    A stick-slip boundary beside an edge knot is new: the edge's knot serves the pressure's
    square root, not the cusp of q (the rig's step C boundary 0.005 mm inside an edge knot
    at 61 pairs). One within ``apart`` of another boundary knot is not: a third C0 knot
    inside 0.008 mm raised the rig at 71 pairs from 0.40 to 1.00 % of f p0 away from the
    transitions (docs/explanation/adaptive.rst, "Limits").
    """

    def new(values: np.ndarray, knots: np.ndarray) -> np.ndarray:
        if not knots.size:
            return np.asarray(values, float)
        return np.array([v for v in values if np.min(np.abs(knots - v)) > apart], float)

    edges = new(handed.edges, settled.edges)
    boundaries = new(handed.boundaries, settled.boundaries)
    if not (edges.size or boundaries.size):
        return None
    return Transitions(
        np.sort(np.concatenate([settled.edges, edges])),
        np.sort(np.concatenate([settled.boundaries, boundaries])),
    )


def _from_first_level(first, coarse_pairs: int, settings: AdaptiveSettings) -> bool:
    """Whether the level after a coarse one of ``coarse_pairs`` takes its knots from the
    uniform ``first`` level instead: the finest level solved before it.

    A budget below twice ``settings.first`` solves an aligned level of half the budget (for
    the estimate's pair ratio of 2), coarser than the uniform first level: it locates the
    transitions worse and places fewer of them (16 pairs: 6 knots). Its transitions handed
    on made the 36-pair reference scene worse than the 31 (0.83 against 0.77 % of p0 away
    from the transitions); the first level's give 0.80 / 0.78 % at P = 60 / 160, and the
    rig at 31 to 51 pairs 1.49 / 1.53 / 0.67 / 0.80 % in q against 4.0 / 4.0 / 0.73 /
    1.19 %. Node-to-node faces only: on the mixed faces (paired by projection) 51 pairs
    fell from 1.11 to 0.59 % while 61 stays at 0.95 %, a rise over the band
    (docs/explanation/adaptive.rst, "Limits").
    """
    return coarse_pairs < settings.first and isinstance(first.simulation.pair, NodeToNodePair)


def run_adaptive(
    simulation, settings: AdaptiveSettings | None = None, *, progress=None
) -> AdaptiveResult:
    """Solve, find the transitions, re-mesh aligned, and re-solve until tolerance or budget.

    Levels: a uniform first level of ``settings.first`` pairs, then aligned levels of about
    doubling pair counts up to the budget, each with its knots moved onto its own discrete
    transitions (:func:`settle`) and handing them to the next; the run stops early when the
    estimate from the last two aligned levels is below the tolerance. ``progress(description,
    total)`` (optional) returns a bar advanced once per level.
    """
    start = time.perf_counter()
    pair = simulation.pair
    family = pair.upper.family
    settings = (settings or AdaptiveSettings()).for_family(family)
    degree = pair.upper.face_refinement(pair.upper_tag).degree
    counts = _level_pairs(settings, family, degree)
    first = remesh(simulation, np.array([]), min(settings.first, counts[-1]), ratio=1.0)
    bar = progress("adaptive levels", len(counts) + 1) if progress is not None else None
    levels = [_solve(first)]
    if bar is not None:
        bar.update(1)
    found = [transitions(levels[0])]
    # mirrored knots while the faces and the transitions are mirror images (settle)
    symmetric = symmetric_faces(simulation)
    estimated: dict = {}
    previous = None
    notes: list[str] = []
    handed = found[-1]
    coarse = True  # whether the knots handed on come from a coarse level (no fallback bound)
    for index, pairs in enumerate(counts):
        # the first aligned level only hands on transitions and a coarse error; any later
        # one may be the answer (the estimate can stop the run there)
        if index == 0:
            iterations, tolerance = settings.coarse_iterations, settings.coarse_tolerance
        else:
            iterations, tolerance = settings.edge_iterations, settings.edge_tolerance
        count = handed.all.size
        settled_before = index > 0 and not coarse
        solved, used, residual, symmetric = settle(
            simulation, handed, pairs, settings, iterations, tolerance, relative=index > 0,
            reach=FALLBACK_REACH if index > 0 and not coarse else None, after=levels[-1],
            symmetric=symmetric,
        )  # fmt: skip
        if used[-1].all.size < count:
            notes.append(
                f"{count} transitions were merged into {used[-1].all.size} to fit {pairs} "
                "pairs (each C0 knot costs a point): the error at a merged transition is "
                "larger than the estimate; raise the budget"
            )
        levels += solved
        found += used
        # hand on every transition of the settled level, not only the placed knots: those
        # merged to fit it, and those the coarser levels could not see (a slip zone
        # narrower than their spacing: the rig's step A at its leading edge)
        spacings = float(np.median(knot_spacings(solved[-1], used[-1])))
        coarse = solved[-1].steps[0].x.size < settings.first or not isinstance(
            solved[-1].simulation.pair, NodeToNodePair
        )
        reach = (COARSE_HAND_ON_REACH if coarse else HAND_ON_REACH) * spacings
        handed = refound(solved[-1], used[-1], reach)
        apart = MERGE * float(np.ptp(estimate.positions(solved[-1])))
        own = own_transitions(used[-1], handed, apart)
        if settled_before and index == len(counts) - 1 and own is not None:
            # the last level found transitions no coarser level saw (the rig's step C
            # stick-slip boundary at 0.641 mm, 0.005 mm inside an edge knot: q 1.06 %
            # of f p0 at 61 pairs against 0.67 % at 41): it has no next level to hand them
            # to, so it is settled again with a knot on each (docs/explanation/adaptive.rst)
            again, more, residual, symmetric = settle(
                simulation, own, pairs, settings, iterations, tolerance, relative=True,
                reach=FALLBACK_REACH, after=None, symmetric=symmetric,
            )  # fmt: skip
            levels += again
            found += more
            solved, used = solved + again, used + more
        if index == 0 and _from_first_level(levels[0], pairs, settings):
            handed = found[0]
        if bar is not None:
            bar.update(1)
        if previous is not None:
            estimated = estimate.estimate_errors(previous, solved[-1], at="coarse")
            worst = max(max(e["e_p_max"], e["e_q_max"]) for e in estimated.values())
            if worst < settings.tolerance:
                break
        previous = solved[-1]
    if residual > 2.0 * settings.edge_tolerance:
        notes.append(
            f"the last level's knots would still move by {residual:.2g} of their point "
            "spacing (settled: below "
            f"{settings.edge_tolerance:g}): the error next to them is larger than the estimate"
        )
    if bar is not None:
        bar.close()
    return AdaptiveResult(
        levels=tuple(levels),
        transitions=tuple(found[1:]),
        estimate=estimated,
        seconds=time.perf_counter() - start,
        notes=tuple(notes),
    )
