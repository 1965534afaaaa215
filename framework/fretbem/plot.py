"""Matplotlib figures of a contact simulation: tractions, displacements, stick/slip maps.

``draw`` is a ``functools.singledispatch`` function drawing geometry (a Boundary, a
discretised segment, a Body, a ContactPair); plugins extend it with ``draw.register``.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Sequence
from pathlib import Path

import matplotlib

if "matplotlib.pyplot" not in sys.modules and "MPLBACKEND" not in os.environ:
    matplotlib.use("Agg")  # files only, unless the user already chose a backend

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .basis import Basis
from .body import Body
from .contact import STATE_NAMES, ContactPair
from .geometry.boundary import Boundary
from .results import SimulationResult, StepResult

FIGURE_STEPS = ("B", "C", "D", "E")
STATE_COLORS = ("#d9d9d9", "#4c72b0", "#dd5544")  # separated, stick, slip
DPI = 120


def _as_list(results) -> list[SimulationResult]:
    return [results] if isinstance(results, SimulationResult) else list(results)


def _label(result: SimulationResult) -> str:
    d = result.describe()
    return f"{d['basis']} p={d['degree']}, {d['pairs']} pairs"


def _reference(results: Sequence[SimulationResult]):
    """The first analytical reference among the results (None if there is none)."""
    return next((r.simulation.reference for r in results if r.simulation.reference), None)


def _scale(results) -> tuple[float, str]:
    """Abscissa scale and label: x/a with a Hertz reference, else x in mm."""
    ref = _reference(results)
    return (ref.hertz.half_width, "x / a") if ref is not None else (1.0, "x (mm)")


def _steps(results, steps: Sequence[str]) -> list[str]:
    names = {s.name for s in results[0].steps}
    chosen = [name for name in steps if name in names]
    if not chosen:
        raise ValueError(f"none of the steps {list(steps)} is in the results {sorted(names)}")
    return chosen


def _history(result: SimulationResult, name: str) -> list[float]:
    """Tangential loads of the steps up to and including ``name``."""
    k = [s.name for s in result.steps].index(name)
    return [s.tangential for s in result.steps[: k + 1]]


def _grid(n: int, title: str) -> tuple[Figure, np.ndarray]:
    cols = min(n, 2)
    rows = -(-n // cols)
    fig, axes = plt.subplots(
        rows, cols, figsize=(5.2 * cols, 3.6 * rows + 0.8), squeeze=False, layout="constrained"
    )
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    fig.suptitle(title)
    return fig, axes.flat


def _error_text(results, name: str, key: str = "e_q_max", label: str = "max $e_q$") -> str:
    """A title line with each result's error ``key`` at step ``name`` (empty without theory)."""
    parts = []
    for r in results:
        errors = r[name].errors
        if errors and errors.get(key) is not None:
            parts.append(f"{r.describe()['basis']} {100 * errors[key]:.2f} %")
    return f"\n{label}: " + ", ".join(parts) if parts else ""


def _step_title(step: StepResult) -> str:
    return f"step {step.name}: P = {step.normal:g}, Q = {step.tangential:g} N/mm"


def traction_figure(
    results: SimulationResult | Sequence[SimulationResult], steps: Sequence[str] = FIGURE_STEPS
) -> Figure:
    """Pressure p and shear q along the contact at each step, with theory (paper Fig. 4)."""
    results = _as_list(results)
    names = _steps(results, steps)
    scale, xlabel = _scale(results)
    ref = _reference(results)
    fig, axes = _grid(len(names), "Contact tractions (traction of the upper body on the lower)")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, name in zip(axes, names, strict=False):
        for i, r in enumerate(results):
            s, c = r[name], colors[i % len(colors)]
            ax.plot(s.x / scale, s.pressure, "o", ms=3.5, color=c, label=f"p, {_label(r)}")
            ax.plot(s.x / scale, s.shear, "s", ms=3.5, mfc="none", color=c, label=f"q, {_label(r)}")
        if ref is not None:
            span = max(np.abs(r[name].x).max() for r in results)
            fine = np.linspace(-span, span, 801)
            q = ref.shear_traction(fine, _history(results[0], name))
            ax.plot(fine / scale, ref.hertz.pressure(fine), "k-", lw=1, label="p, analytical")
            ax.plot(fine / scale, q, "k--", lw=1, label="q, analytical")
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.set_title(_step_title(results[0][name]) + _error_text(results, name))
        ax.set_xlabel(xlabel)
        ax.set_ylabel("traction (MPa)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 3), fontsize=8)
    return fig


def displacement_figure(
    results: SimulationResult | Sequence[SimulationResult], steps: Sequence[str] = FIGURE_STEPS
) -> Figure:
    """Relative normal (top row) and tangential (bottom row) displacements per step (Fig. 5)."""
    results = _as_list(results)
    names = _steps(results, steps)
    scale, xlabel = _scale(results)
    fig, axes = plt.subplots(
        2, len(names), figsize=(4.0 * len(names), 6.4), squeeze=False, sharex=True,
        sharey="row", layout="constrained",
    )  # fmt: skip
    fig.suptitle("Relative displacements at the node pairs (upper minus lower body)")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    gap = results[0].simulation.pair.geometry["gap"]
    rows = (("normal_displacement", "$u_n$", "o"), ("tangential_displacement", "$u_t$", "s"))
    for col, name in enumerate(names):
        for row, (field, symbol, marker) in enumerate(rows):
            ax = axes[row, col]
            for i, r in enumerate(results):
                s, c = r[name], colors[i % len(colors)]
                ax.plot(s.x / scale, 1e3 * getattr(s, field), marker + "-", ms=3, lw=0.8,
                        mfc="none", color=c, label=_label(r))  # fmt: skip
            ax.axhline(0.0, color="0.6", lw=0.5)
            ax.grid(alpha=0.3)
            ax.set_ylabel(f"{symbol} (µm)" if col == 0 else "")
        x = results[0][name].x / scale
        axes[0, col].plot(x, -1e3 * gap, ":", color="0.3", lw=1.2, label="$-g$ (gap closed)")
        axes[0, col].set_title(_step_title(results[0][name]))
        axes[1, col].set_xlabel(xlabel)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=8)
    return fig


def _edges(x: np.ndarray) -> np.ndarray:
    """Cell edges around sorted centres x (midpoints, ends extended by half a spacing)."""
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def stick_slip_figure(result: SimulationResult | Sequence[SimulationResult]) -> Figure:
    """State of every pair (separated, stick, slip) at every step, with theory's stick zone."""
    results = _as_list(result)
    scale, xlabel = _scale(results)
    fig, axes = plt.subplots(
        1, len(results), figsize=(6.0 * len(results), 3.6), squeeze=False, layout="constrained"
    )
    cmap = ListedColormap(STATE_COLORS)
    norm = BoundaryNorm(np.arange(len(STATE_NAMES) + 1) - 0.5, cmap.N)
    for ax, r in zip(axes.flat, results, strict=True):
        states = np.array([s.states for s in r.steps])
        x = r.steps[0].x / scale
        rows = np.arange(len(r.steps) + 1) - 0.5
        ax.pcolormesh(_edges(x), rows, states, cmap=cmap, norm=norm, edgecolors="w", lw=0.3)
        ref = r.simulation.reference
        if ref is not None:
            a = ref.hertz.half_width / scale
            for k, s in enumerate(r.steps):
                c = ref.stick_zone(_history(r, s.name))[1] / scale
                ax.plot([-c, c], [k, k], "k|", ms=14, mew=2)
            ax.axvline(-a, color="k", ls=":", lw=1)
            ax.axvline(a, color="k", ls=":", lw=1)
        ax.set_yticks(range(len(r.steps)), [s.name for s in r.steps])
        ax.invert_yaxis()
        ax.set_xlabel(xlabel)
        ax.set_ylabel("load step")
        ax.set_title(f"pair states, {_label(r)}")
    handles = [Patch(color=c, label=n) for c, n in zip(STATE_COLORS, STATE_NAMES, strict=True)]
    if _reference(results) is not None:
        handles.append(
            Line2D(
                [], [], color="k", marker="|", ls="", ms=10, mew=2, label="analytical stick zone ±c"
            )
        )
        handles.append(Line2D([], [], color="k", ls=":", label="Hertz half-width ±a"))
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8)
    return fig


def save_figures(
    result_or_results: SimulationResult | Sequence[SimulationResult], directory: str | Path
) -> list[Path]:
    """Write tractions.png, displacements.png and states.png into ``directory``."""
    results = _as_list(result_or_results)
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    steps = [n for n in FIGURE_STEPS if n in {s.name for s in results[0].steps}]
    steps = steps or [s.name for s in results[0].steps]
    figures = {
        "tractions.png": traction_figure(results, steps),
        "displacements.png": displacement_figure(results, steps),
        "states.png": stick_slip_figure(results),
    }
    paths = []
    for name, fig in figures.items():
        fig.savefig(directory / name, dpi=DPI)
        plt.close(fig)
        paths.append(directory / name)
    return paths


# -- geometry ---------------------------------------------------------------------------------
def _axes(ax):
    if ax is None:
        _, ax = plt.subplots(layout="constrained")
        ax.set_aspect("equal")
    return ax


@functools.singledispatch
def draw(obj, ax=None, **style):
    """Draw ``obj`` (Boundary, Basis, Body, ContactPair) on ``ax``; returns the axes."""
    kinds = ", ".join(t.__name__ for t in draw.registry if t is not object)
    raise TypeError(f"draw() cannot draw a {type(obj).__name__}; it draws {kinds}")


@draw.register
def _(obj: Boundary, ax=None, **style):
    """The exact segment curves, one colour per segment, labelled by tag."""
    ax = _axes(ax)
    for segment in obj.segments:
        points = segment.curve.points(np.linspace(0.0, 1.0, 65))
        (line,) = ax.plot(*points.T, label=segment.tag, **style)
        middle = segment.curve.points([0.5])[0]
        ax.annotate(segment.tag, middle, color=line.get_color(), fontsize=7)
    return ax


@draw.register
def _(obj: Basis, ax=None, points_per_element: int = 8, **style):
    """One discretised segment: its geometry sampled on every element, element ends marked."""
    ax = _axes(ax)
    local = np.linspace(-1.0, 1.0, points_per_element)
    elements = np.repeat(np.arange(obj.n_elements), points_per_element)
    points = obj.geometry(elements, np.tile(local, obj.n_elements))[0]
    (line,) = ax.plot(*points.T, **style)
    ends = points.reshape(obj.n_elements, points_per_element, 2)[:, [0, -1]].reshape(-1, 2)
    ax.plot(*ends.T, "o", color=line.get_color(), mfc="none", ms=3)
    return ax


@draw.register
def _(obj: Body, ax=None, **style):
    """Every discretised segment of the body and its collocation points."""
    ax = _axes(ax)
    for basis in obj.segments:
        draw(basis, ax, **style)
    ax.plot(*obj.collocation.points.T, ".", color="k", ms=2)
    return ax


@draw.register
def _(obj: ContactPair, ax=None, **style):
    """Both bodies of the pair."""
    ax = _axes(ax)
    draw(obj.upper, ax, **style)
    draw(obj.lower, ax, **style)
    return ax
