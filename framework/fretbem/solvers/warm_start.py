"""Newton starts taken from a solved run of the same history on another mesh of the contact.

The adaptive mode (:mod:`fretbem.accuracy.adaptive`) solves the same load history on a
sequence of contact meshes whose pairs stand at nearby places. Each increment's Newton
iteration converges once its separated/stick/slip pattern is right (the functions are
piecewise linear in x: the first step on a pattern solves that pattern's linear problem
exactly, whatever x it starts from), so a start whose pattern is the last mesh's, read at
the new pairs' positions, leaves only the pairs next to a transition to be corrected.
:func:`fretbem.simulation.run` given a :class:`WarmStart` starts every increment there;
an increment whose warm start fails is solved again from the usual start (the previous
increment's state), so a run converges wherever the cold run does.

A pattern read at the nearest solved pair changes halfway between two solved pairs. Where
the new mesh has a C0 knot on one of the solved run's own pairs (a finer level's knots
handed on from a settled coarser one, whose knots sit on its transitions), the pattern
changes at that pair instead: a new pair between it and the solved run's next pair starts
in that next pair's state (``knots``). At budget 61 the first 61-pair level of the
reference scene then takes 5 Newton iterations instead of 15.

Only the start changes: the path (each increment's stick reference, the previous state's
slip) is the run's own, and the converged unknowns are the same solution of the same
increment, to the solver's tolerance (tests/framework/solvers/test_warm_start.py).
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.law import ContactState

__all__ = ["WarmStart"]


def _along(points: np.ndarray, tangent: np.ndarray) -> np.ndarray:
    return np.asarray(points, float) @ tangent


@attrs.frozen(eq=False)
class WarmStart:
    """Per step and increment, the pattern and tractions a solved run reached, by position.

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        The solved run's pair positions.
    steps : tuple of (str, tuple of (states, pressure, shear))
        Per load step its name and, per increment, the pair states and tractions reached.
    knots : ndarray, shape (k, 2)
        Points of the new mesh's C0 knots (empty: none); a knot on one of the solved run's
        pairs is where the pattern changes (the module's note).
    """

    points: np.ndarray
    steps: tuple
    knots: np.ndarray = attrs.field(
        factory=lambda: np.zeros((0, 2)), converter=lambda k: np.asarray(k, float).reshape(-1, 2)
    )

    @classmethod
    def of(cls, result, knots: np.ndarray | None = None) -> WarmStart:
        """The starts a :class:`~fretbem.results.SimulationResult` offers (its increments),
        for a mesh with C0 knots at the points ``knots`` (optional)."""
        points = result.simulation.pair.pairing().points
        steps = tuple(
            (step.name, tuple((r.states, r.pressure, r.shear) for r in step.increments))
            for step in result.steps
        )
        knots = np.zeros((0, 2)) if knots is None else knots
        return cls(points=np.asarray(points, float), steps=steps, knots=knots)

    def mapper(self, problem) -> _Mapper:
        """The starts of a run on the condensed ``problem`` (its pairs' positions)."""
        return _Mapper(self, problem)


class _Mapper:
    """The warm starts of one run: each increment's pattern read at the problem's pairs."""

    def __init__(self, warm: WarmStart, problem) -> None:
        tangents = problem.pairing.tangents
        tangent = tangents.mean(axis=0)
        tangent = tangent / max(float(np.linalg.norm(tangent)), 1e-300)
        old = _along(warm.points, tangent)
        new = _along(problem.pairing.points, tangent)
        self.order = np.argsort(old, kind="stable")
        old = old[self.order]
        self.old, self.new = old, new
        # nearest solved pair of every new one (the pattern is piecewise constant)
        right = np.clip(np.searchsorted(old, new), 1, max(old.size - 1, 1))
        left = right - 1
        if old.size > 1:
            closer_left = np.abs(new - old[left]) <= np.abs(old[right] - new)
            self.nearest = np.where(closer_left, left, right)
        else:
            self.nearest = np.zeros(new.size, int)
        self.beside = _beside_knots(old, new, _along(warm.knots, tangent))
        self.layout = problem.layout
        self.steps = {name: increments for name, increments in warm.steps}

    def start(self, name: str, increment: int, increments: int, state: ContactState):
        """The start of increment ``increment`` (1-based) of ``increments`` of step ``name``
        from ``state``, or None when the solved run has no such increment."""
        solved = self.steps.get(name)
        if solved is None or len(solved) != increments or self.old.size == 0:
            return None
        states, pressure, shear = solved[increment - 1]
        layout = self.layout
        x = np.array(state.x, dtype=float)  # block displacements and rotations: the usual start
        x[layout.pressure] = np.interp(self.new, self.old, np.asarray(pressure)[self.order])
        x[layout.shear] = np.interp(self.new, self.old, np.asarray(shear)[self.order])
        ordered = np.asarray(states)[self.order]
        pattern = ordered[self.nearest].astype(int)
        pairs, left, right, side = self.beside
        if pairs.size:  # the change at the knot where the two solved pairs around differ
            changes = ordered[left] != ordered[right]
            pattern[pairs[changes]] = ordered[side[changes]]
        return ContactState(x=x, states=pattern, slip=state.slip, virgin=False)


#: a knot lies on a pair when closer than this fraction of the new pairs' extent
ON_PAIR = 1e-9


def _beside_knots(old: np.ndarray, new: np.ndarray, knots: np.ndarray) -> tuple:
    """The new pairs between a knot on a solved pair and the solved pair next to it: their
    indices, the two solved pairs around each (sorted indices) and the one on its side of
    the knot (the knot's neighbour). Only a bracket of two solved pairs holding that one
    knot counts; a new pair on the knot itself keeps the nearest pair's state."""
    empty = np.zeros(0, int)
    if old.size < 2 or not knots.size:
        return empty, empty, empty, empty
    knots = np.sort(knots)
    tol = ON_PAIR * max(float(np.ptp(new)), 1e-300)
    right = np.clip(np.searchsorted(old, new), 1, old.size - 1)
    left = right - 1
    first = np.searchsorted(knots, old[left] - tol, side="left")
    last = np.searchsorted(knots, old[right] + tol, side="right")
    knot = knots[np.minimum(first, knots.size - 1)]
    on_left, on_right = np.abs(knot - old[left]) <= tol, np.abs(knot - old[right]) <= tol
    inside = (new > old[left] + tol) & (new < old[right] - tol)
    keep = (last - first == 1) & (on_left | on_right) & inside & (np.abs(new - knot) > tol)
    pairs = np.flatnonzero(keep)
    left, right = left[keep], right[keep]
    side = np.where(on_left[keep], right, left)
    return pairs, left, right, side
