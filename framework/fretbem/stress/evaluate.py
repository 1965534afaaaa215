"""Stresses of a solved simulation at user points, for one step or every step.

Each body model supplies its own evaluation matrix (linear in the body's boundary data):
Somigliana's identity for a boundary-element body, integrated Flamant line loads for a
half-plane. The matrix is built once per (body, points) and every load step is then a
matrix product, so a whole cycle costs about as much as one step.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np

from .errors import StressInputError
from .halfplane import halfplane_stress_matrix
from .somigliana import StressSettings, somigliana_operator

__all__ = ["StressEvaluator", "stresses"]

BODIES = ("lower", "upper")


def _step_index(result, step) -> int:
    names = [s.name for s in result.steps]
    if isinstance(step, (int, np.integer)):
        if not -len(names) <= int(step) < len(names):
            raise StressInputError(f"step {step} out of range: the result has {len(names)} steps")
        return int(step) % len(names)
    if step not in names:
        raise StressInputError(f"no step {step!r}; the steps are {names}")
    return names.index(step)


def _points(points) -> np.ndarray:
    points = np.asarray(points, dtype=float)
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
        return self.problem.solutions(step.unknowns, step.loads)[self.body]

    def _build(self):
        from fretbem.halfplane import HalfPlaneBody

        model = self.model
        material = model.material
        if isinstance(model, HalfPlaneBody):
            return _HalfPlaneOperator.of(model, self.points)
        if hasattr(model, "segments"):  # a boundary-element body
            return somigliana_operator(
                model.segments,
                self.points,
                shear_modulus=material.shear_modulus,
                nu=material.nu,
                plane_stress=material.plane_stress,
                settings=self.settings,
            )
        raise StressInputError(
            f"body {self.body!r} is a {type(model).__name__}, which has no stress evaluation; "
            "stresses exist for boundary-element and half-plane bodies"
        )

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


@attrs.frozen(eq=False)
class _HalfPlaneOperator:
    """Half-plane stresses as a matrix over the face traction coefficients, plus the bulk."""

    matrix: np.ndarray  # (m, 3, N, 2)
    collocation: np.ndarray  # E: coefficients -> node values
    mirror: bool
    nu: float
    plane_stress: bool
    bulk: bool

    @classmethod
    def of(cls, model, points: np.ndarray) -> _HalfPlaneOperator:
        surface = model.surface
        face_y = surface.points[:, 1]
        upper = model.side == "upper"
        level = face_y.min() if upper else face_y.max()
        depth = (points[:, 1] - level) if upper else (level - points[:, 1])
        if np.any(depth < -1e-9 * max(np.ptp(surface.points[:, 0]), 1.0)):
            i = int(np.argmin(depth))
            raise StressInputError(
                f"point {points[i].tolist()} lies outside the half-plane "
                f"({'above' if not upper else 'below'} its surface y = {level:g})"
            )
        matrix = halfplane_stress_matrix(surface.face, points[:, 0], np.maximum(depth, 0.0))
        return cls(
            matrix,
            surface.collocation_matrix,
            upper,
            model.material.nu,
            model.material.plane_stress,
            "bulk" in model.load_names,
        )

    def evaluate(self, solution) -> np.ndarray:
        tractions = np.asarray(solution.tractions, float)
        if self.mirror:  # the upper body is the lower one reflected in its surface line
            tractions = tractions * np.array([1.0, -1.0])
        coefficients = np.linalg.solve(self.collocation, tractions)
        stress = np.einsum("pcnk,nk->pc", self.matrix, coefficients)
        if self.mirror:
            stress[:, 2] *= -1.0
        if self.bulk:
            stress[:, 0] += float(solution.loads.get("bulk", 0.0))
        szz = 0.0 if self.plane_stress else self.nu * (stress[:, 0] + stress[:, 1])
        return np.column_stack([stress, np.broadcast_to(szz, len(stress))])


def stresses(result, step: int | str, points, body: str = "lower") -> np.ndarray:
    """Stress (m, 4) [sxx, syy, sxy, szz] in MPa, global frame, at ``points`` (m, 2) of
    ``body`` ("lower" or "upper") at the end of ``step`` (name or index).

    Bulk stress and loading block are included through the body's boundary data. For many
    steps at the same points use :class:`StressEvaluator`, which builds the matrix once.
    """
    return StressEvaluator(result, points, body).step(step)
