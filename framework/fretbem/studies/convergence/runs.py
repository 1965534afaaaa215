"""One fixed-pairs run of the convergence study: the case, its measurement, traction changes.

A case is the reference scene with a family, a degree, a pair count, and optionally larger
bodies or a scaled refinement of the rest; :func:`measure` runs it and returns one row of
``convergence.csv`` (timings are medians over repeats, memory the tracemalloc peak of one
more run).
"""

from __future__ import annotations

import gc
import math
import statistics
import time
import tracemalloc
from collections.abc import Iterable

import attrs
import numpy as np

from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import run

from .io import ERROR_STEPS, ERRORS, STEPS


@attrs.frozen
class Case:
    """One run of the study.

    Attributes
    ----------
    family : str
    degree : int or None
        None for the family's default.
    pairs : int
    bodies : float
        Size of both bodies over the scene's (width and height scaled; 1 = the scene).
    rest : float
        Factor on the element counts of flanks, sides and top/bottom (1 = the scene's).
    """

    family: str
    degree: int | None
    pairs: int
    bodies: float = 1.0
    rest: float = 1.0

    def scene(self) -> CattaneoMindlinScene:
        base = CattaneoMindlinScene()
        count = lambda n: max(1, round(n * self.rest))  # noqa: E731
        return attrs.evolve(
            base,
            basis=self.family,
            degree=self.degree,
            pairs=self.pairs,
            width=base.width * self.bodies,
            height=base.height * self.bodies,
            flank_elements=count(base.flank_elements),
            side_elements=count(base.side_elements),
            top_elements=count(base.top_elements),
        )

    @property
    def baseline(self) -> Case:
        """The same run with the scene's refinement of the rest."""
        return attrs.evolve(self, rest=1.0)

    def label(self) -> str:
        degree = "" if self.degree is None else f" p={self.degree}"
        extra = "" if self.bodies == 1 else f", bodies x{self.bodies:g}"
        extra += "" if self.rest == 1 else f", rest x{self.rest:g}"
        return f"{self.family}{degree}, {self.pairs} pairs{extra}"


def _median(values: Iterable[float]) -> float:
    return float(statistics.median(list(values)))


def measure(case: Case, repeats: int = 1, memory: bool = True):
    """Run ``case``; returns (row without the rest-change columns, result of the first run).

    Wall time is from building the scene to the last step; every timing is the median over
    ``repeats`` runs. With ``memory`` one more run is traced with tracemalloc.
    """
    walls, timings, first = [], [], None
    for _ in range(max(1, repeats)):
        gc.collect()
        tic = time.perf_counter()
        result = run(cattaneo_mindlin(case.scene()))
        walls.append(time.perf_counter() - tic)
        timings.append({**result.timings, **{f"solve_{s.name}": s.seconds for s in result.steps}})
        if first is None:
            first = result
    peak = math.nan
    if memory:
        gc.collect()
        tracemalloc.start()
        try:
            run(cattaneo_mindlin(case.scene()))
            peak = tracemalloc.get_traced_memory()[1] / 2**20
        finally:
            tracemalloc.stop()
    scene = case.scene()
    info = first.describe()
    steps = {s.name: s for s in first.steps}
    row: dict[str, object] = {
        "family": case.family,
        "degree": info["degree"],
        "pairs": info["pairs"],
        "bodies": case.bodies,
        "width": scene.width,
        "height": scene.height,
        "rest": case.rest,
        "flank_elements": scene.flank_elements,
        "side_elements": scene.side_elements,
        "top_elements": scene.top_elements,
        "dofs": info["dofs"],
    }
    for error in ERRORS:
        for name in ERROR_STEPS:
            row[f"{error}_{name}"] = steps[name].errors[error]
        row[error] = max(steps[name].errors[error] for name in ERROR_STEPS)
    for name in STEPS:
        row[f"iterations_{name}"] = steps[name].iterations
    row["iterations"] = sum(s.iterations for s in first.steps)
    median = lambda key: _median(t[key] for t in timings)  # noqa: E731
    row["assembly_s"] = median("assembly")
    row["factorisation_s"] = median("factorisation")
    row["condensation_s"] = median("condensation")  # includes the factorisation
    for name in STEPS:
        row[f"solve_{name}_s"] = median(f"solve_{name}")
    row["steps_s"] = median("steps")
    row["run_s"] = median("total")
    row["wall_s"] = _median(walls)
    row["peak_memory_mib"] = peak
    row["repeats"] = max(1, repeats)
    return row, first


def tractions(result) -> tuple[float, float, list[tuple[np.ndarray, ...]]]:
    """p0, f p0 and per step the pair positions, p and q: what traction_change compares."""
    reference = result.simulation.reference
    p0 = reference.hertz.peak_pressure
    return p0, reference.friction * p0, [(s.x, s.pressure, s.shear) for s in result.steps]


def traction_change(result, baseline) -> tuple[float, float]:
    """Largest change of p (over p0) and of q (over f p0) at any pair and step.

    ``result`` and ``baseline`` are SimulationResults or ``tractions`` of them.
    """
    (_, _, ours), (p0, fp0, theirs) = (
        r if isinstance(r, tuple) else tractions(r) for r in (result, baseline)
    )
    dp = dq = 0.0
    for (xa, pa, qa), (xb, pb, qb) in zip(ours, theirs, strict=True):
        if xa.shape != xb.shape or not np.allclose(xa, xb, rtol=0, atol=1e-9):
            raise ValueError("traction_change needs runs with the same contact pairs")
        dp = max(dp, float(np.max(np.abs(pa - pb))) / p0)
        dq = max(dq, float(np.max(np.abs(qa - qb))) / fp0)
    return dp, dq


__all__ = ["Case", "measure", "traction_change", "tractions"]
