"""Stress results as files: CSV tables per request and VTK structured grids per step.

The VTK files (one ``.vts`` per step and a ``.pvd`` collection whose timestep is the step
index) open in ParaView as a time series. pyvista is imported only here, when a grid is
written.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from fretbem.views.markup import quote_attribute

__all__ = ["von_mises", "write_grid_vtk", "write_stress_csv"]

COLUMNS = ("sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "von_mises")


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress of [sxx, syy, sxy, szz] (..., 4), sigma_zz included."""
    sxx, syy, sxy, szz = np.moveaxis(np.asarray(stress, float), -1, 0)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy**2)


def write_stress_csv(
    path: str | Path,
    steps: Sequence[str],
    points: np.ndarray,
    stress: np.ndarray,
    depth: np.ndarray | None = None,
) -> Path:
    """One row per (step, point): step, x, y, [depth,] the four stresses and von Mises (MPa).

    ``stress`` is (n_steps, m, 4); ``points`` (m, 2) in mm.
    """
    path = Path(path)
    stress = np.asarray(stress, float)
    head = ["step", "x_mm", "y_mm"] + (["depth_mm"] if depth is not None else [])
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(head + [f"{c}_MPa" for c in COLUMNS])
        vm = von_mises(stress)
        for k, name in enumerate(steps):
            for i, (x, y) in enumerate(points):
                row = [name, f"{x:.9g}", f"{y:.9g}"]
                if depth is not None:
                    row.append(f"{depth[i]:.9g}")
                row += [f"{v:.9g}" for v in stress[k, i]] + [f"{vm[k, i]:.9g}"]
                writer.writerow(row)
    return path


def write_grid_vtk(
    directory: str | Path,
    name: str,
    steps: Sequence[str],
    points: np.ndarray,
    stress: np.ndarray,
) -> Path:
    """A structured grid per step (``name_<k>.vts``) and ``name.pvd`` listing them with
    timestep k. ``points`` (ny, nx, 2), ``stress`` (n_steps, ny, nx, 4)."""
    import pyvista as pv

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    x = points[..., 0].T[:, :, None]
    y = points[..., 1].T[:, :, None]
    grid = pv.StructuredGrid(x, y, np.zeros_like(x))
    entries = []
    for k, step in enumerate(steps):
        block = grid.copy()
        values = np.asarray(stress[k])
        for c, column in enumerate(COLUMNS[:4]):
            block.point_data[column] = values[..., c].ravel()  # C order of (ny, nx) = x fastest
        block.point_data["von_mises"] = von_mises(values).ravel()
        file = directory / f"{name}_{k}.vts"
        block.save(file)
        entries.append(
            f'    <DataSet timestep="{k}" part="0" file={quote_attribute(file.name)} '
            f"name={quote_attribute(str(step))}/>"
        )
    pvd = directory / f"{name}.pvd"
    pvd.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
        + "\n".join(entries)
        + "\n  </Collection>\n</VTKFile>\n"
    )
    return pvd
