"""Fretting maps: the regime, or any output column, over two varied parameters of a sweep.

The regime map colours each case full stick, partial slip or gross slip (refused) and draws
the line where the peak tangential load equals f times the normal load (interpolated from
the cases' own Q_peak - f P_max, so it works on any pair of axes: P-Q, f-Q, P-f...).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .cases import REGIMES
from .spec import SweepSpecError
from .units import axis_label

REGIME_COLOURS = {"full stick": "#4477aa", "partial slip": "#ddaa33", "gross slip": "#bb5566"}


def _select(table, x: str, y: str, where: Mapping[str, Any] | None):
    """Rows with the ``where`` values; each (x, y) must then be one case."""
    for column in (x, y, *(where or {})):
        if column not in table:
            raise SweepSpecError(
                f"the sweep table has no column {column!r}; map over varied parameters "
                f"(columns {[c for c in table.columns if '.' in c or c == 'friction'][:12]}...)"
            )
    rows = table
    for column, value in (where or {}).items():
        rows = rows[np.isclose(rows[column].astype(float), float(value))]
    if rows.duplicated([x, y]).any():
        raise SweepSpecError(
            f"several cases share each ({x}, {y}): fix the other varied parameters with "
            "where = {path = value}"
        )
    return rows


def _grid(rows, x: str, y: str, values) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    xs = np.unique(rows[x].to_numpy(dtype=float))
    ys = np.unique(rows[y].to_numpy(dtype=float))
    grid = np.full((len(ys), len(xs)), np.nan)
    i = np.searchsorted(xs, rows[x].to_numpy(dtype=float))
    j = np.searchsorted(ys, rows[y].to_numpy(dtype=float))
    grid[j, i] = values
    return xs, ys, grid


def _boundary(ax, rows, x: str, y: str) -> bool:
    """Contour ``Q_peak = f P_max`` over the cases (the gross-slip boundary), or for cyclic
    cases ``A = A_t`` (the energy ratio at its transition value); False if absent."""
    if {"energy_ratio", "transition_ratio"} <= set(rows.columns):
        # cyclic cases: the partial / gross slip transition A = A_t
        g = rows["energy_ratio"].to_numpy(float) - rows["transition_ratio"].to_numpy(float)
        return _zero_contour(ax, rows, x, y, g, "A = A_t (gross slip onset)")
    if not {"Q_peak", "P_max", "friction"} <= set(rows.columns):
        return False
    q, f, p = (rows[c].to_numpy(float) for c in ("Q_peak", "friction", "P_max"))
    return _zero_contour(ax, rows, x, y, q - f * p, "|Q| = f P")


def _zero_contour(ax, rows, x: str, y: str, g, label: str) -> bool:
    """Draw the zero contour of g over the (x, y) grid of ``rows``; False where it has none."""
    xs, ys, grid = _grid(rows, x, y, g)
    if len(xs) < 2 or len(ys) < 2 or not (np.nanmin(grid) < 0 < np.nanmax(grid)):
        return False
    ax.contour(xs, ys, grid, levels=[0.0], colors="k", linewidths=1.5, linestyles="--")
    ax.plot([], [], "k--", label=label)
    return True


def _axes():
    """Axes on a new Figure, without pyplot (no backend switch, nothing left open)."""
    from matplotlib.figure import Figure

    return Figure(figsize=(6.4, 4.8), layout="constrained").add_subplot()


def regime_map(table, x: str, y: str, *, where=None, ax=None, title: str | None = None):
    """Fretting map: regime of each case over parameters ``x`` and ``y`` (matplotlib Axes)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    rows = _select(table, x, y, where)
    codes = np.array([REGIMES.index(r) if r in REGIMES else np.nan for r in rows["regime"]])
    xs, ys, grid = _grid(rows, x, y, codes)
    if ax is None:
        ax = _axes()
    cmap = ListedColormap([REGIME_COLOURS[r] for r in REGIMES])
    ax.pcolormesh(
        xs, ys, np.ma.masked_invalid(grid), cmap=cmap, vmin=-0.5, vmax=2.5, shading="nearest"
    )
    handles = [Patch(color=REGIME_COLOURS[r], label=r) for r in REGIMES]
    if np.isnan(grid).any():
        handles.append(Patch(facecolor="white", edgecolor="grey", label="failed / missing"))
    _boundary(ax, rows, x, y)
    line, label = ax.get_legend_handles_labels()
    ax.legend(
        handles=handles + line,
        labels=[h.get_label() for h in handles] + label,
        loc="upper left",
        bbox_to_anchor=(1.02, 1.0),
        borderaxespad=0.0,
        fontsize=9,
    )
    ax.set_xlabel(axis_label(x))
    ax.set_ylabel(axis_label(y))
    ax.set_title(title or f"fretting regime ({len(rows)} cases)")
    return ax


def column_map(table, column: str, x: str, y: str, *, where=None, ax=None, title=None):
    """Map of a numeric output ``column`` (e.g. ``stick_width.B``, life) over ``x`` and ``y``."""

    rows = _select(table, x, y, where)
    if column not in rows:
        outputs = sorted(c for c in rows.columns if "." in c and c not in (x, y))
        raise SweepSpecError(f"no output column {column!r}; columns include {outputs[:16]}")
    values = rows[column].to_numpy(dtype=float)
    xs, ys, grid = _grid(rows, x, y, values)
    if ax is None:
        ax = _axes()
    mesh = ax.pcolormesh(xs, ys, np.ma.masked_invalid(grid), shading="nearest", cmap="viridis")
    ax.figure.colorbar(mesh, ax=ax, label=axis_label(column))
    if _boundary(ax, rows, x, y):
        ax.legend(loc="upper left", framealpha=0.9, fontsize=9)
    ax.set_xlabel(axis_label(x))
    ax.set_ylabel(axis_label(y))
    ax.set_title(title or f"{column} (blank: gross slip or failed)")
    return ax


def _name(*parts: str) -> str:
    return "map-" + "-".join(re.sub(r"[^A-Za-z0-9_]+", "_", p).strip("_") for p in parts) + ".png"


def default_maps(paths: Sequence[str]) -> list[dict]:
    """The regime over the first two varied parameters (over the one, as a line plot)."""
    if len(paths) >= 2:
        return [{"x": paths[0], "y": paths[1], "column": "regime"}]
    return [{"x": paths[0], "column": "regime"}] if paths else []


def line_plot(table, column: str, x: str, *, where=None, ax=None, title=None):
    """``column`` (or the regime, as its code) against one varied parameter ``x``."""
    rows = _select(table, x, x, where)
    if column not in rows:
        outputs = sorted(c for c in rows.columns if "." in c and c != x)
        raise SweepSpecError(f"no output column {column!r}; columns include {outputs[:16]}")
    rows = rows.sort_values(x)
    if ax is None:
        ax = _axes()
    if column == "regime":
        codes = [REGIMES.index(r) if r in REGIMES else np.nan for r in rows["regime"]]
        ax.plot(rows[x].to_numpy(float), codes, "o-")
        ax.set_yticks(range(len(REGIMES)), REGIMES)
    else:
        ax.plot(rows[x].to_numpy(float), rows[column].to_numpy(float), "o-")
        ax.set_ylabel(column)
    ax.set_xlabel(x)
    ax.set_title(title or f"{column} over {x} ({len(rows)} cases)")
    return ax


MAP_KEYS = {"x", "y", "column", "where", "title"}


def map_entries(spec) -> list[Mapping]:
    """The sweep's ``[[maps]]`` (or the default) as a list of tables."""
    maps = spec.options.get("maps", default_maps(spec.paths))
    return [maps] if isinstance(maps, Mapping) else list(maps)


def check_maps(spec, columns: set[str] | None) -> None:
    """Refuse, before any case is solved, a ``[[maps]]`` entry that cannot be drawn.

    ``x``, ``y`` and the ``where`` keys must be varied parameters; ``column`` must be one
    the sweep will write (``columns``; None when an output does not declare its columns,
    then only the parameters are checked).
    """
    paths = list(spec.paths)
    for k, entry in enumerate(map_entries(spec)):
        here = f"[[maps]] #{k + 1}"
        if not isinstance(entry, Mapping) or "x" not in entry:
            raise SweepSpecError(f"{here} needs x (and y for a map), key paths; got {entry!r}")
        unknown = set(entry) - MAP_KEYS
        if unknown:
            raise SweepSpecError(f"{here}: unknown keys {sorted(unknown)}; the keys are "
                                 f"{sorted(MAP_KEYS)}")  # fmt: skip
        axes = [entry["x"], *([entry["y"]] if "y" in entry else [])]
        where = entry.get("where") or {}
        if not isinstance(where, Mapping):
            raise SweepSpecError(f"{here}: where must be a table {{path = value}}")
        for name in (*axes, *where):
            if name not in paths:
                raise SweepSpecError(
                    f"{here}: {name!r} is not a varied parameter; map over {paths}"
                )
        column = entry.get("column", "regime")
        if not isinstance(column, str):
            raise SweepSpecError(f"{here}: column must be a column name, got {column!r}")
        if columns is not None and column not in columns and column not in paths:
            close = sorted(c for c in columns if c.split(".")[0] == column.split(".")[0])
            raise SweepSpecError(
                f"{here}: the sweep writes no column {column!r}"
                + (f"; did you mean one of {close[:8]}" if close else "")
                + f"; columns: {sorted(columns)[:24]}"
            )


def draw_maps(table, spec, directory: str | Path) -> list[Path]:
    """Draw the sweep's ``[[maps]]`` (x, y, column, optional where) into ``directory``.

    An entry without ``y`` is a line plot of ``column`` over ``x``."""
    check_maps(spec, None)
    figures = []
    for entry in map_entries(spec):
        column = entry.get("column", "regime")
        where = entry.get("where")
        if "y" not in entry:
            ax = line_plot(table, column, entry["x"], where=where, title=entry.get("title"))
            path = Path(directory) / _name(column, entry["x"])
            ax.figure.savefig(path, dpi=120)
            figures.append(path)
            continue
        if column == "regime":
            ax = regime_map(table, entry["x"], entry["y"], where=where, title=entry.get("title"))
        else:
            ax = column_map(
                table, column, entry["x"], entry["y"], where=where, title=entry.get("title")
            )
        path = Path(directory) / _name(column, entry["x"], entry["y"])
        ax.figure.savefig(path, dpi=120)
        figures.append(path)
    return figures


__all__ = [
    "REGIME_COLOURS",
    "check_maps",
    "column_map",
    "default_maps",
    "draw_maps",
    "line_plot",
    "map_entries",
    "regime_map",
]
