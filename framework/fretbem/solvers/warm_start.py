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
    """

    points: np.ndarray
    steps: tuple

    @classmethod
    def of(cls, result) -> WarmStart:
        """The starts a :class:`~fretbem.results.SimulationResult` offers (its increments)."""
        points = result.simulation.pair.pairing().points
        steps = tuple(
            (step.name, tuple((r.states, r.pressure, r.shear) for r in step.increments))
            for step in result.steps
        )
        return cls(points=np.asarray(points, float), steps=steps)

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
        pattern = np.asarray(states)[self.order][self.nearest].astype(int)
        return ContactState(x=x, states=pattern, slip=state.slip, virgin=False)
