"""The evaluated stresses of a ``[stress]`` request: one record, written as CSV/VTK files by
:func:`fretbem.stress.run.run_stress_request` and labelled as an xarray Dataset.

Stress arrays are (steps, ..., 4): sigma_xx, sigma_yy, sigma_xy, sigma_zz in MPa.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.views.cf import CONVENTIONS, attributes, clean_attrs
from fretbem.views.display import html_table

from .output import COLUMNS, von_mises

__all__ = ["StressLineResult", "StressResult"]


@attrs.frozen(eq=False)
class StressLineResult:
    """A depth profile: its global points (n, 2), depths (n,) and stresses (steps, n, 4)."""

    points: np.ndarray
    depths: np.ndarray
    stress: np.ndarray


@attrs.frozen(eq=False)
class StressResult:
    """Everything a ``[stress]`` request evaluated.

    Attributes
    ----------
    body : str
        "lower" or "upper".
    steps : tuple of str
    points, point_stress : ndarray or None
        Explicit points (m, 2) and their stresses (steps, m, 4).
    lines : tuple of StressLineResult
    grid_x, grid_depth, grid_points, grid_stress : ndarray or None
        Grid abscissae (nx,), depths (ny,), points (ny, nx, 2), stresses (steps, ny, nx, 4).
    half_width : float or None
        The a edge positions were placed for (None when no position names an edge).
    """

    body: str
    steps: tuple[str, ...]
    points: np.ndarray | None = None
    point_stress: np.ndarray | None = None
    lines: tuple[StressLineResult, ...] = ()
    grid_x: np.ndarray | None = None
    grid_depth: np.ndarray | None = None
    grid_points: np.ndarray | None = None
    grid_stress: np.ndarray | None = None
    half_width: float | None = None

    def _parts(self) -> list[str]:
        parts = []
        if self.points is not None:
            parts.append(f"{len(self.points)} points")
        parts += [
            f"line at x={line.points[0, 0]:.4g} ({len(line.depths)} depths)" for line in self.lines
        ]
        if self.grid_points is not None:
            parts.append(f"grid {len(self.grid_x)} x {len(self.grid_depth)}")
        return parts

    def __repr__(self) -> str:
        hot = self.hot_spot()
        peak = ""
        if hot is not None:
            h = hot["sigma_xx"]
            peak = (
                f"; max sigma_xx {h['value']:.4g} MPa at step {h['step']}, "
                f"x={h['x']:.4g}, y={h['y']:.4g}"
            )
        return (
            f"<StressResult {self.body} body, {len(self.steps)} steps, "
            f"{', '.join(self._parts()) or 'nothing evaluated'}{peak}>"
        )

    def _repr_html_(self) -> str:
        rows = [
            ("body", self.body),
            ("steps", ", ".join(self.steps[:12])),
            ("evaluated", ", ".join(self._parts()) or "nothing"),
        ]
        for name, h in (self.hot_spot() or {}).items():
            rows.append(
                (
                    f"max {name} (MPa)",
                    f"{h['value']:.4g} at step {h['step']}, x = {h['x']:.4g}, y = {h['y']:.4g} mm",
                )
            )
        return html_table(("", ""), rows, caption="stresses")

    def hot_spot(self) -> dict | None:
        """Largest sigma_xx and largest von Mises over every evaluated point and step:
        ``{"sigma_xx": {value, step, x, y}, "von_mises": {...}}`` (None: nothing evaluated)."""
        parts = []
        if self.points is not None:
            parts.append((self.points, self.point_stress))
        parts += [(line.points, line.stress) for line in self.lines]
        if self.grid_points is not None:
            parts.append(
                (self.grid_points.reshape(-1, 2), self.grid_stress.reshape(len(self.steps), -1, 4))
            )
        if not parts:
            return None
        points = np.concatenate([p for p, _ in parts])
        stress = np.concatenate([s for _, s in parts], axis=1)
        out = {}
        for name, values in (("sigma_xx", stress[..., 0]), ("von_mises", von_mises(stress))):
            k, i = np.unravel_index(int(np.argmax(values)), values.shape)
            out[name] = {
                "value": float(values[k, i]),
                "step": self.steps[k],
                "x": float(points[i, 0]),
                "y": float(points[i, 1]),
            }
        return out

    def to_xarray(self):
        """The stresses as an :class:`xarray.Dataset`: ``point_<c>`` (step, point),
        ``line<k>_<c>`` (step, line<k>_depth), ``grid_<c>`` (step, grid_depth, grid_x) for
        each component c of sigma_xx, sigma_yy, sigma_xy, sigma_zz, von_mises (MPa)."""
        import xarray as xr

        data, coords = {}, {"step": ("step", np.array(self.steps, dtype=str))}

        def add(prefix, dims, stress):
            values = np.concatenate([stress, von_mises(stress)[..., None]], axis=-1)
            for j, name in enumerate(COLUMNS):
                data[f"{prefix}_{name}"] = (("step", *dims), values[..., j], attributes(name))

        if self.points is not None:
            coords["point_x"] = ("point", self.points[:, 0], attributes("x"))
            coords["point_y"] = ("point", self.points[:, 1], attributes("y"))
            add("point", ("point",), self.point_stress)
        for k, line in enumerate(self.lines):
            dim = f"line{k}_depth"
            coords[dim] = (dim, line.depths, attributes("depth"))
            coords[f"line{k}_x"] = ((), float(line.points[0, 0]), attributes("x"))
            add(f"line{k}", (dim,), line.stress)
        if self.grid_points is not None:
            coords["grid_x"] = ("grid_x", self.grid_x, attributes("x"))
            coords["grid_depth"] = ("grid_depth", self.grid_depth, attributes("depth"))
            add("grid", ("grid_depth", "grid_x"), self.grid_stress)
        meta = {
            "Conventions": CONVENTIONS,
            "title": f"fretbem stresses in the {self.body} body",
            "body": self.body,
            "sign_conventions": "tension > 0; depth measured into the body from its contact "
            "surface at the same x",
            "half_width": self.half_width,
        }
        return xr.Dataset(data, coords=coords, attrs=clean_attrs(meta))
