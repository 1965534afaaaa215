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
from .result import StressLineResult, StressResult

__all__ = [
    "evaluate_stress_request",
    "most_loaded_step",
    "run_stress_request",
    "write_stress_result",
]


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


def evaluate_stress_request(result, request: StressRequest, *, progress=None) -> StressResult:
    """Evaluate ``request`` for ``result``: every point, line and grid at its steps (edge
    positions such as ``"trailing-edge"`` placed for the run's contact half-width).
    ``progress(description, total)`` (optional) returns a bar advanced after each part."""
    half_width = None
    if request.uses_edges:  # "trailing-edge" and the like, placed for this run's a
        half_width, centre, _ = contact_half_width(result)
        request = request.resolved(half_width, centre)
    steps = _step_names(result, request)
    side = request.body

    parts = (request.points is not None) + len(request.lines) + (request.grid is not None)
    bar = progress("stresses", parts) if progress is not None else None

    def evaluate(points):
        values = StressEvaluator(result, points, side).steps(steps)
        if bar is not None:
            bar.update(1)
        return values

    model = result.simulation.prepare().pair.side(side)[0]
    fields = {"body": side, "steps": tuple(steps), "half_width": half_width}
    if request.points is not None:
        fields.update(points=request.points, point_stress=evaluate(request.points))
    lines = []
    for line in request.lines:
        pts, depths = line_points(model, line, side)
        lines.append(StressLineResult(pts, depths, evaluate(pts)))
    fields["lines"] = tuple(lines)
    if request.grid is not None:
        pts, xs, depths = grid_points(model, request.grid, side)
        stress = evaluate(pts.reshape(-1, 2)).reshape(len(steps), *pts.shape[:2], 4)
        fields.update(grid_x=xs, grid_depth=depths, grid_points=pts, grid_stress=stress)
    if bar is not None:
        bar.close()
    return StressResult(**fields)


def run_stress_request(result, request: StressRequest, directory: str | Path) -> dict[str, Path]:
    """Evaluate ``request`` for ``result`` and write its files into ``directory``.

    Returns the written paths by role: points.csv, line_<k>.csv, grid.csv, grid.pvd,
    surface_sigma_xx.png, stress_contours.png.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    done = evaluate_stress_request(result, request)
    return write_stress_result(result, request, done, directory)


def write_stress_result(
    result, request: StressRequest, done: StressResult, directory: Path
) -> dict[str, Path]:
    """The files of an evaluated request (CSV tables, the grid's VTK series, figures)."""
    steps, side = list(done.steps), done.body
    written: dict[str, Path] = {}
    model = result.simulation.prepare().pair.side(side)[0]
    if done.points is not None:
        written["points"] = write_stress_csv(
            directory / "stress_points.csv", steps, done.points, done.point_stress
        )
    for k, line in enumerate(done.lines):
        written[f"line_{k}"] = write_stress_csv(
            directory / f"stress_line_{k}.csv", steps, line.points, line.stress, line.depths
        )
    if done.grid_points is not None:
        pts, xs, depths, stress = done.grid_points, done.grid_x, done.grid_depth, done.grid_stress
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
        surface = StressEvaluator(result, pts, side).steps(steps)[..., 0]
        written["surface"] = plot_surface_sigma_xx(
            directory / "surface_sigma_xx.png", xs, steps, surface
        )
    return written
