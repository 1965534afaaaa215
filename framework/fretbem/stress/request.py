"""Where to evaluate stresses: points, depth profiles (lines) and grids graded toward the
surface, as a user asks for them (Python or the scene file's ``[stress]`` table).

Depths are measured below the body's contact surface at the same x (for the lower body:
down from its top face; for the upper body: up from its bottom face), so a line or grid
follows a curved face. Lengths in mm.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import attrs
import numpy as np

from fretbem.validators import file_integer, file_list, file_number, file_string

from .edges import EdgePosition, parse_position
from .errors import StressRequestError

__all__ = [
    "StressGrid",
    "StressLine",
    "StressRequest",
    "stress_request_from_dict",
    "surface_level",
]


def _positive(instance, attribute, value) -> None:
    if not (np.isfinite(value) and value > 0):
        raise StressRequestError(f"{attribute.name} must be a finite number > 0, got {value!r}")


def _whole(value):
    """A count: a whole number (2.7, true and "5" refused, 5.0 accepted from Python)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise StressRequestError(f"a count must be a whole number, got {value!r}")
    if value != int(value):
        raise StressRequestError(f"a count must be a whole number, got {value!r}")
    return int(value)


def _real(value):
    """A number (true and "1.0" refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise StressRequestError(f"expected a number, got {value!r}")
    return float(value)


def _count(instance, attribute, value) -> None:
    if value < 2:
        raise StressRequestError(f"{attribute.name} must be an integer >= 2, got {value!r}")


def _graded_depths(depth: float, n: int, grading: float) -> np.ndarray:
    """n depths from 0 to ``depth``, spacing growing by ``grading`` (last / first spacing)."""
    if grading == 1.0:
        return np.linspace(0.0, depth, n)
    # geometric spacing: h_k = h_0 r^k, r^(n - 2) = grading
    ratio = grading ** (1.0 / max(n - 2, 1))
    steps = ratio ** np.arange(n - 1)
    return depth * np.concatenate([[0.0], np.cumsum(steps)]) / steps.sum()


@attrs.frozen
class StressLine:
    """A depth profile below the surface point at abscissa ``x``.

    Attributes
    ----------
    x : float or EdgePosition
        Abscissa (mm) of the surface point, e.g. the trailing contact edge.
    depth : float
        Deepest point (mm) below the surface.
    n : int
        Points, the first on the surface.
    grading : float
        Spacing of the deepest interval over the shallowest (1 for uniform).
    """

    x: float | EdgePosition = attrs.field(converter=parse_position)
    depth: float = attrs.field(converter=_real, validator=_positive)
    n: int = attrs.field(default=50, converter=_whole, validator=_count)
    grading: float = attrs.field(default=20.0, converter=_real, validator=_positive)

    def resolved(self, a: float, centre: float = 0.0) -> StressLine:
        """The same line at a number x (an edge position placed for half-width ``a``)."""
        if isinstance(self.x, EdgePosition):
            return attrs.evolve(self, x=self.x.resolve(a, centre))
        return self

    def depths(self) -> np.ndarray:
        """Depths (n,) from 0 to ``depth``."""
        return _graded_depths(self.depth, self.n, self.grading)


@attrs.frozen
class StressGrid:
    """A rectangle below the contact, rows graded toward the surface.

    Attributes
    ----------
    x : (float, float)
        Abscissa range (mm).
    depth : float
        Depth of the deepest row (mm).
    nx, ny : int
        Columns and rows (the first row on the surface).
    grading : float
        Row spacing at the bottom over row spacing at the surface.
    """

    x: tuple[float, float] = attrs.field(converter=lambda v: tuple(_real(a) for a in v))
    depth: float = attrs.field(converter=_real, validator=_positive)
    nx: int = attrs.field(default=81, converter=_whole, validator=_count)
    ny: int = attrs.field(default=41, converter=_whole, validator=_count)
    grading: float = attrs.field(default=20.0, converter=_real, validator=_positive)

    def __attrs_post_init__(self) -> None:
        if len(self.x) != 2 or not self.x[0] < self.x[1]:
            raise StressRequestError(
                f"grid x must be [x_min, x_max] with x_min < x_max, got {self.x}"
            )

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """Abscissae (nx,) and depths (ny,)."""
        return np.linspace(*self.x, self.nx), _graded_depths(self.depth, self.ny, self.grading)


@attrs.frozen
class StressRequest:
    """Which stresses to compute and write.

    Attributes
    ----------
    body : str
        "lower" (the specimen) or "upper" (the pad).
    steps : tuple of str or None
        Step names; None for every step.
    points : ndarray (m, 2) or None
        Explicit global points (x, y).
    lines : tuple of StressLine
    grid : StressGrid or None
    figures : bool
        Surface sigma_xx over the steps and the contour maps.
    vtk : bool
        The grid as a VTK structured grid per step (ParaView time series).
    """

    body: str = attrs.field(default="lower")
    steps: tuple[str, ...] | None = attrs.field(
        default=None, converter=lambda v: None if v is None else tuple(str(s) for s in v)
    )
    points: np.ndarray | None = attrs.field(default=None, eq=False)
    lines: tuple[StressLine, ...] = attrs.field(default=(), converter=tuple)
    grid: StressGrid | None = None
    figures: bool = True
    vtk: bool = True

    def __attrs_post_init__(self) -> None:
        if self.body not in ("lower", "upper"):
            raise StressRequestError(f"[stress] body must be 'lower' or 'upper', got {self.body!r}")
        if self.points is not None and self.symbolic_points:
            where = "[stress] points"
            rows = [
                (
                    parse_position(p[0], where),
                    file_number(f"{where} y", p[1], error=StressRequestError),
                )
                for p in self.points
            ]
            object.__setattr__(self, "points", tuple(rows))
            return
        if self.points is not None:
            try:
                pts = np.asarray(self.points, float)
            except (TypeError, ValueError, OverflowError):  # text, an int past a float's range
                raise StressRequestError(
                    "[stress] points must be a list of [x, y] pairs of finite numbers, got "
                    "entries that are not numbers"
                ) from None
            if pts.ndim != 2 or pts.shape[1] != 2 or not np.all(np.isfinite(pts)):
                raise StressRequestError(
                    "[stress] points must be a list of [x, y] pairs of finite numbers, got "
                    f"an array of shape {pts.shape}"
                )
            object.__setattr__(self, "points", pts)

    @property
    def symbolic_points(self) -> bool:
        """Whether a point's x names a contact edge (resolved against the result)."""
        if self.points is None or isinstance(self.points, np.ndarray):
            return False
        try:
            return any(isinstance(p[0], (str, EdgePosition)) for p in self.points if len(p) == 2)
        except TypeError:
            return False

    def resolved(self, a: float, centre: float = 0.0) -> StressRequest:
        """The request with every edge position placed for half-width ``a`` about ``centre``."""
        points = self.points
        if self.symbolic_points:
            points = np.array(
                [[x.resolve(a, centre) if isinstance(x, EdgePosition) else x, y]
                 for x, y in self.points], dtype=float,
            )  # fmt: skip
        lines = tuple(line.resolved(a, centre) for line in self.lines)
        return attrs.evolve(self, points=points, lines=lines)

    @property
    def uses_edges(self) -> bool:
        """Whether any position names a contact edge."""
        return self.symbolic_points or any(isinstance(x.x, EdgePosition) for x in self.lines)


_KEYS = {"body", "steps", "points", "line", "grid", "figures", "vtk"}
_LINE_KEYS = {"x", "depth", "n", "grading"}
_GRID_KEYS = {"x", "depth", "nx", "ny", "grading"}


def _table(raw, keys: set[str], where: str) -> dict:
    if not isinstance(raw, Mapping):
        raise StressRequestError(f"{where} must be a table, got {type(raw).__name__}")
    unknown = set(raw) - keys
    if unknown:
        raise StressRequestError(
            f"{where} has unknown key(s) {sorted(unknown)}; the keys are {sorted(keys)}"
        )
    return dict(raw)


def _strict(raw: dict, where: str) -> None:
    """No coercion from the file: counts whole, numbers not booleans or strings."""
    for key, value in raw.items():
        here = f"{where} {key}"
        if key in ("n", "nx", "ny"):
            file_integer(here, value, low=2, error=StressRequestError)
        elif key == "x" and isinstance(value, str):
            parse_position(value, where)  # an edge name, checked by its own parser
        elif key == "x" and isinstance(value, list):
            file_list(here, value, lambda w, v: file_number(w, v, error=StressRequestError),
                      length=2, error=StressRequestError)  # fmt: skip
        else:
            file_number(here, value, error=StressRequestError)


def _build(cls, raw: dict, where: str):
    _strict(raw, where)
    try:
        return cls(**raw)
    except StressRequestError as err:
        raise StressRequestError(f"{where}: {err}") from None
    except (TypeError, ValueError) as err:
        raise StressRequestError(f"{where}: {err}") from None


def stress_request_from_dict(raw: Mapping) -> StressRequest:
    """Read a scene file's ``[stress]`` table (already parsed TOML) into a StressRequest.

    Keys: body, steps, points ([[x, y], ...]), line (a table or an array of tables with x,
    depth, n, grading), grid (x = [x0, x1], depth, nx, ny, grading), figures, vtk.
    """
    raw = _table(raw, _KEYS, "[stress]")
    lines = raw.pop("line", [])
    if isinstance(lines, Mapping):
        lines = [lines]
    if not isinstance(lines, Sequence):
        raise StressRequestError("[stress] line must be a table or an array of tables")
    raw["lines"] = tuple(
        _build(StressLine, _table(item, _LINE_KEYS, f"[stress.line] #{i + 1}"), "[stress.line]")
        for i, item in enumerate(lines)
    )
    if "grid" in raw:
        raw["grid"] = _build(
            StressGrid, _table(raw["grid"], _GRID_KEYS, "[stress.grid]"), "[stress.grid]"
        )
    if isinstance(raw.get("steps"), str):
        raw["steps"] = [raw["steps"]]
    if "steps" in raw:
        file_list("[stress] steps", raw["steps"],
                  lambda w, v: file_string(w, v, error=StressRequestError), min_length=1,
                  error=StressRequestError)  # fmt: skip
    if "body" in raw:
        file_string("[stress] body", raw["body"], ("lower", "upper"), error=StressRequestError)
    for key in ("figures", "vtk"):
        if key in raw and not isinstance(raw[key], bool):
            raise StressRequestError(f"[stress] {key} must be true or false, got {raw[key]!r}")
    try:
        return StressRequest(**raw)
    except StressRequestError:
        raise
    except (TypeError, ValueError) as err:
        raise StressRequestError(f"[stress]: {err}") from None


def surface_level(model, x: np.ndarray, side: str) -> np.ndarray:
    """y of the body's contact-side surface at abscissae x (:meth:`Body.surface_level`)."""
    x = np.asarray(x, float)
    best = model.surface_level(x, side)
    if not np.all(np.isfinite(best)):
        bad = x[~np.isfinite(best)][0]
        raise StressRequestError(f"x = {bad:g} mm is outside the body's extent; shorten the grid")
    return best


def line_points(model, line: StressLine, side: str) -> tuple[np.ndarray, np.ndarray]:
    """Global points (n, 2) of a depth profile and their depths (n,)."""
    if isinstance(line.x, EdgePosition):
        raise StressRequestError(
            f"line x = '{line.x}' names a contact edge: place it first with "
            "request.resolved(a) (run_stress_request does this with the run's a)"
        )
    depths = line.depths()
    level = surface_level(model, np.array([line.x]), side)[0]
    sign = -1.0 if side == "lower" else 1.0
    return np.column_stack([np.full(line.n, line.x), level + sign * depths]), depths


def grid_points(model, grid: StressGrid, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Global points (ny, nx, 2) of a grid, and its abscissae (nx,) and depths (ny,)."""
    xs, depths = grid.axes()
    level = surface_level(model, xs, side)
    sign = -1.0 if side == "lower" else 1.0
    y = level[None, :] + sign * depths[:, None]
    return np.stack([np.broadcast_to(xs, y.shape), y], axis=-1), xs, depths
