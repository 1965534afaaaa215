"""A solved simulation as a stress-history provider for :func:`fretbem.fatigue.run_fatigue`.

Stresses come from :class:`fretbem.stress.evaluate.StressEvaluator` (Somigliana's identity
for a boundary-element body, Flamant integration for a half-plane), one evaluation matrix
per point set and a matrix product per step. Points are [x, depth] below the body's contact
surface (depth measured from the surface at that x); the driver of the default cycle is the
tangential load per step, and the Ruiz inputs are the contact shear, the surface sigma_xx
and the pairs' accumulated slip.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.stress.evaluate import StressEvaluator
from fretbem.stress.request import surface_level

from .errors import FatigueInputError
from .providers import SurfaceHistory

__all__ = ["SimulationStressHistory"]

#: point sets whose stresses a provider keeps (each at most a map's grid: 0.3 MB for the
#: rig's 1,891 points over five steps)
KEPT_POINT_SETS = 16


@attrs.frozen(eq=False)
class SimulationStressHistory:
    """Stress history of one body of a :class:`~fretbem.results.SimulationResult`.

    Attributes
    ----------
    result : SimulationResult
        The solved simulation.
    body : str
        "lower" (the specimen, default) or "upper". Stress components are in the global
        frame (y up), so for the lower body the conventions of :mod:`.providers` hold.
    surface_depth : float
        Depth (mm) below the surface where "surface" stresses are evaluated; a small positive
        value keeps the boundary-element evaluation off the boundary.
    """

    result: object
    body: str = "lower"
    surface_depth: float = 0.0
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        if self.body not in ("lower", "upper"):
            raise FatigueInputError(f"body must be 'lower' or 'upper', got {self.body!r}")
        if not getattr(self.result, "steps", None):
            raise FatigueInputError("the simulation result has no steps")

    @property
    def n_steps(self) -> int:
        """Number of load steps of the result."""
        return len(self.result.steps)

    @property
    def driver(self) -> np.ndarray:
        """Tangential load per step: its reversals define the default cycle."""
        return np.array([s.tangential for s in self.result.steps], dtype=float)

    @property
    def elastic_constants(self) -> tuple[float, float]:
        """(E, nu) of the evaluated body: the strains of the fatigue parameters use them
        when the fatigue material does not give its own."""

        material = StressEvaluator(self.result, np.zeros((1, 2)), self.body).model.material
        return float(material.E), float(material.nu)

    @property
    def contact_half_width(self) -> float:
        """Half the extent of the largest contact (positive pressure) over the steps, mm."""
        widths = []
        for s in self.result.steps:
            touching = s.x[np.asarray(s.pressure) > 0]
            if touching.size:
                widths.append(0.5 * (touching.max() - touching.min()))
        if not widths:
            raise FatigueInputError("no step of the result has contact pressure")
        return float(max(widths))

    def _global(self, points: np.ndarray) -> np.ndarray:
        model = StressEvaluator(self.result, np.zeros((1, 2)), self.body).model
        x, depth = points[:, 0], points[:, 1]
        level = surface_level(model, x, self.body)
        sign = -1.0 if self.body == "lower" else 1.0
        return np.stack([x, level + sign * depth], axis=1)

    def stress_at(self, points: np.ndarray) -> np.ndarray:
        """Stress (n_steps, n, 4) at points (n, 2) = [x, depth], global frame.

        The latest point sets' stresses are kept (a copy is returned): the fatigue search asks
        the same points for each criterion whose hot spot is the same (its fine scan, the hot
        spot, the critical-distance points and the depth profile)."""

        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if np.any(pts[:, 1] < 0):
            raise FatigueInputError("depth must be >= 0 (below the contact surface)")
        key = ("stress_at", pts.tobytes())
        kept = self._cache.get(key)
        if kept is None:
            kept = StressEvaluator(self.result, self._global(pts), self.body).steps()
            if len(self._cache) >= KEPT_POINT_SETS:
                self._cache.pop(next(iter(self._cache)))
            self._cache[key] = kept
        return kept.copy()

    def surface_history(self, x: np.ndarray) -> SurfaceHistory:
        """Contact shear, surface sigma_xx and accumulated slip at surface abscissae x."""
        x = np.asarray(x, dtype=float)
        steps = self.result.steps
        shear = np.stack([np.interp(x, s.x, s.shear, left=0.0, right=0.0) for s in steps])
        slip = np.stack(
            [np.interp(x, s.x, s.tangential_displacement, left=0.0, right=0.0) for s in steps]
        )
        pts = np.stack([x, np.full_like(x, self.surface_depth)], axis=1)
        sxx = self.stress_at(pts)[:, :, 0]
        return SurfaceHistory(x=x, shear_traction=shear, surface_stress_xx=sxx, slip=slip)
