"""Stresses of a solved simulation at user points, for one step or every step.

Each body model supplies its own evaluation matrix (linear in the body's boundary data,
:meth:`fretbem.body.Body.stress_operator`): Somigliana's identity for a boundary-element
body, integrated Flamant line loads for a half-plane. The matrix is built once per (body,
points) and every load step is then a matrix product, so a whole cycle costs about as much
as one step.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.bem.stresses import StressSettings
from fretbem.sliding.result import step_solutions
from fretbem.validators import shown

from .errors import StressInputError

__all__ = ["StressEvaluator", "stresses"]

BODIES = ("lower", "upper")


def _step_index(result, step) -> int:
    names = [s.name for s in result.steps]
    if isinstance(step, (bool, np.bool_)):
        raise StressInputError(f"step must be a step's name or index, got {step!r}; give e.g. 'B'")
    if isinstance(step, (int, np.integer)):
        if not -len(names) <= int(step) < len(names):
            raise StressInputError(
                f"step {shown(step)} out of range: the result has {len(names)} steps"
            )
        return int(step) % len(names)
    if step not in names:
        raise StressInputError(f"no step {step!r}; the steps are {names}")
    return names.index(step)


def _points(points) -> np.ndarray:
    try:
        points = np.asarray(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise StressInputError(
            "points must be a finite array of shape (m, 2) [x, y] of numbers, got "
            + (shown(points) if isinstance(points, str) else "entries that are not floats")
        ) from None
    if points.ndim == 1 and points.size == 2:
        points = points[None]
    if points.ndim != 2 or points.shape[1] != 2 or not np.all(np.isfinite(points)):
        raise StressInputError(
            f"points must be a finite array of shape (m, 2) [x, y], got shape {points.shape}"
        )
    return points


@attrs.define(eq=False)
class StressEvaluator:
    """Stresses of one body of a solved simulation at fixed points, any step.

    Attributes
    ----------
    result : SimulationResult
    points : ndarray (m, 2)
        Global x, y (mm), inside the body (or on its boundary).
    body : str
        "lower" or "upper".
    settings : StressSettings
        Quadrature of the boundary-element evaluation.
    """

    result: object
    points: np.ndarray = attrs.field(converter=_points)
    body: str = "lower"
    settings: StressSettings = attrs.field(factory=StressSettings)
    _operator: object = attrs.field(init=False, default=None, repr=False)

    def __attrs_post_init__(self) -> None:
        if self.body not in BODIES:
            raise StressInputError(f"body must be 'lower' or 'upper', got {self.body!r}")

    @property
    def problem(self):
        """The simulation's condensed contact problem (cached by the pair)."""
        return self.result.simulation.prepare()

    @property
    def model(self):
        """The body object evaluated."""
        return self.problem.pair.side(self.body)[0]

    def _solution(self, index: int):
        step = self.result.steps[index]
        if getattr(step, "pair", None) is not None:  # finite sliding: the step's own pairing
            if self.body == "upper" and getattr(step.pair, "turn", 0.0):
                raise StressInputError(
                    f"step {step.name!r}: the pad slid along an arc and turned with it "
                    f"({step.pair.turn:.4g} rad), so its fields are in its own turned axes, not "
                    "the global frame the stresses are given in; evaluate the specimen's "
                    "stresses ([stress] body = 'lower'), or slide on a flat specimen"
                )
            return step_solutions(self.result, step)[self.body]
        return self.problem.solutions(step.unknowns, step.loads)[self.body]

    def _build(self):
        return self.model.stress_operator(self.points, self.settings)

    @property
    def operator(self):
        """The evaluation matrix (built on first use)."""
        if self._operator is None:
            self._operator = self._build()
        return self._operator

    def step(self, step: int | str) -> np.ndarray:
        """(m, 4) [sxx, syy, sxy, szz] MPa, global frame, at the end of ``step``."""
        return self.operator.evaluate(self._solution(_step_index(self.result, step)))

    def steps(self, steps: Sequence[int | str] | None = None) -> np.ndarray:
        """(n_steps, m, 4) for the given steps (all by default)."""
        steps = range(len(self.result.steps)) if steps is None else steps
        return np.stack([self.step(s) for s in steps])


def stresses(result, step: int | str, points, body: str = "lower") -> np.ndarray:
    """Stress (m, 4) [sxx, syy, sxy, szz] in MPa, global frame, at ``points`` (m, 2) of
    ``body`` ("lower" or "upper") at the end of ``step`` (name or index).

    Bulk stress and loading block are included through the body's boundary data. For many
    steps at the same points use :class:`StressEvaluator`, which builds the matrix once.
    """
    return StressEvaluator(result, points, body).step(step)
