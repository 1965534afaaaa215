"""Carry out a StressRequest on a solved simulation: evaluate, write tables, grids, figures."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fretbem.stress.figures import plot_contour_maps, plot_surface_sigma_xx

from .edges import contact_half_width
from .errors import StressRequestError
from .evaluate import StressEvaluator
from .output import write_grid_vtk, write_stress_csv
from .request import StressRequest, grid_points, line_points, surface_level

__all__ = ["most_loaded_step", "run_stress_request"]


def most_loaded_step(result) -> int:
    """Index of the step with the largest absolute Q (the first of equals)."""
    return int(np.argmax([abs(s.tangential) for s in result.steps]))


def _step_names(result, request: StressRequest) -> list[str]:
    names = [s.name for s in result.steps]
    if request.steps is None:
        return names
    unknown = [s for s in request.steps if s not in names]
    if unknown:
        raise StressRequestError(f"[stress] steps {unknown} are not steps of the run ({names})")
    return list(request.steps)


def run_stress_request(result, request: StressRequest, directory: str | Path) -> dict[str, Path]:
    """Evaluate ``request`` for ``result`` and write its files into ``directory``.

    Returns the written paths by role: points.csv, line_<k>.csv, grid.csv, grid.pvd,
    surface_sigma_xx.png, stress_contours.png.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    if request.uses_edges:  # "trailing-edge" and the like, placed for this run's a
        request = request.resolved(*contact_half_width(result)[:2])
    steps = _step_names(result, request)
    side = request.body
    written: dict[str, Path] = {}

    def evaluate(points):
        return StressEvaluator(result, points, side).steps(steps)

    model = result.simulation.prepare().pair.side(side)[0]
    if request.points is not None:
        written["points"] = write_stress_csv(
            directory / "stress_points.csv", steps, request.points, evaluate(request.points)
        )
    for k, line in enumerate(request.lines):
        pts, depths = line_points(model, line, side)
        written[f"line_{k}"] = write_stress_csv(
            directory / f"stress_line_{k}.csv", steps, pts, evaluate(pts), depths
        )
    if request.grid is not None:
        pts, xs, depths = grid_points(model, request.grid, side)
        stress = evaluate(pts.reshape(-1, 2)).reshape(len(steps), *pts.shape[:2], 4)
        flat_depth = np.broadcast_to(depths[:, None], pts.shape[:2]).ravel()
        written["grid"] = write_stress_csv(
            directory / "stress_grid.csv", steps, pts.reshape(-1, 2),
            stress.reshape(len(steps), -1, 4), flat_depth,
        )  # fmt: skip
        if request.vtk:
            written["grid_vtk"] = write_grid_vtk(directory, "stress_grid", steps, pts, stress)
        if request.figures:
            loaded = most_loaded_step(result)
            name = result.steps[loaded].name
            if name in steps:
                step = result.steps[loaded]
                written["contours"] = plot_contour_maps(
                    directory / "stress_contours.png", xs, depths, stress[steps.index(name)],
                    pair_x=np.asarray(step.x), states=np.asarray(step.states),
                    title=f"{side} body, step {name} (Q = {step.tangential:g} N/mm)",
                )  # fmt: skip
    if request.figures:
        x = np.asarray(result.steps[0].x)
        xs = np.linspace(x.min(), x.max(), 201)
        pts = np.column_stack([xs, surface_level(model, xs, side)])
        written["surface"] = plot_surface_sigma_xx(
            directory / "surface_sigma_xx.png", xs, steps, evaluate(pts)[..., 0]
        )
    return written
