"""Matplotlib figures of a contact simulation: tractions, displacements, stick/slip maps.

``draw`` is a ``functools.singledispatch`` function drawing geometry (a Boundary, a
discretised segment, a Body, a ContactPair); plugins extend it with ``draw.register``.
matplotlib is imported on the first figure; figures are pyplot's when pyplot is in use
(notebooks, galleries), else plain Figures on an Agg canvas (the command line).
"""

from __future__ import annotations

import contextlib
import functools
import gc
import io
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from fretbem.basis import Basis
from fretbem.body import Body
from fretbem.contact.pairs import STATE_NAMES, ContactPair
from fretbem.errors import InputError
from fretbem.geometry.boundary import Boundary
from fretbem.results import SimulationResult, StepResult

from .png import write_png

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

STATE_COLORS = ("#d9d9d9", "#4c72b0", "#dd5544")  # separated, stick, slip
DPI = 100
#: at most this many step panels per figure (2 rows x 3 columns); longer histories are
#: summarised by ``history_figure`` and a readable selection of steps, the first included
MAX_PANELS = 6
#: at most this many rows labelled in the pair-state map
MAX_STATE_LABELS = 15
#: titles sit at the top of their axes (no automatic placement: no axis draws labels on top)
TITLE_Y = 1.0
#: legend text size (points): readable when a figure is printed at half a page width
LEGEND_SIZE = 9
#: at most this many intervals between the major ticks of an axis (matplotlib's default
#: puts 9-11 on a panel): matplotlib's cost is per tick, five artists and a label each
TICK_BINS = 5
#: step panel titles in the axes' tick-label size: three families' errors fit on one line
TITLE_SIZE = "medium"


def _pyplot():
    """pyplot, with the Agg backend chosen first unless the user already chose one."""
    if "matplotlib.pyplot" not in sys.modules and "MPLBACKEND" not in os.environ:
        import matplotlib

        matplotlib.use("Agg")  # files only
    import matplotlib.pyplot as plt

    return plt


def _figure(figsize: tuple[float, float]) -> Figure:
    """A new figure: pyplot's when pyplot is in use (notebooks, galleries, ``plt.show``), else
    a plain Figure on an Agg canvas that reads each font's line metrics once
    (:mod:`fretbem.output.canvas`; the command line: no pyplot import, no figure manager)."""
    if "matplotlib.pyplot" in sys.modules:
        return sys.modules["matplotlib.pyplot"].figure(figsize=figsize)
    from matplotlib.figure import Figure

    from .canvas import FigureCanvas

    fig = Figure(figsize=figsize)
    FigureCanvas(fig)
    return fig


def _close(fig: Figure) -> None:
    """Release a figure that pyplot may hold (plain figures are freed with their last use)."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


@contextlib.contextmanager
def _collector_paused():
    """The cyclic garbage collector off while figures are drawn: matplotlib's import and
    artists allocate ~10^5 objects that set off full collections finding almost nothing; the
    figures' own cycles are collected afterwards."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _text_unhinted():
    """Glyphs drawn without FreeType hinting while the files are written (a third less time
    per glyph: the figures draw about 1,500), unless the user chose a hinting."""
    import matplotlib

    if matplotlib.rcParams["text.hinting"] != matplotlib.rcParamsDefault["text.hinting"]:
        return contextlib.nullcontext()
    return matplotlib.rc_context({"text.hinting": "no_hinting"})


def _ticks_in_view(fig: Figure) -> None:
    """Each automatically located axis of ``fig`` given the ticks it shows and their labels,
    before the file is drawn: matplotlib makes a tick (five artists) for every location its
    locator returns, and ``MaxNLocator`` returns one beyond each end of the view, drawn or not
    (a third of the demo's ticks); and it locates and formats the ticks again three times
    per draw of an axis. The same ticks and labels are drawn (an axis whose labels carry an
    offset or a scale, such as "1e-5", keeps its formatter)."""
    from matplotlib.ticker import MaxNLocator

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if not isinstance(axis.get_major_locator(), MaxNLocator):
                continue
            low, high = sorted(axis.get_view_interval())
            slack = 1e-9 * (high - low)  # matplotlib's own test keeps 1e-10 of the view
            locations = axis.get_majorticklocs()
            kept = [x for x in locations if low - slack <= x <= high + slack]
            formatter = axis.get_major_formatter()
            labels = formatter.format_ticks(kept)
            if formatter.get_offset():  # drawn beside the axis: the formatter must stay
                axis.set_ticks(kept)
            else:
                axis.set_ticks(kept, labels)


def _save_png(fig: Figure, path: Path) -> None:
    """``fig`` as a PNG file at :data:`DPI`: drawn by ``savefig`` (every savefig setting
    applied) to raw RGBA pixels on its Agg canvas, encoded by
    :func:`fretbem.output.png.write_png` (no per-row filter search: a third of Pillow's time;
    the same pixels and chunks). A figure on another canvas, or ``savefig.bbox = "tight"``,
    is written by matplotlib."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if isinstance(fig.canvas, FigureCanvasAgg) and matplotlib.rcParams["savefig.bbox"] != "tight":
        raw = io.BytesIO()
        fig.savefig(raw, dpi=DPI, format="rgba")
        shape = np.asarray(fig.canvas.buffer_rgba()).shape  # the renderer savefig drew on
        if raw.tell() == int(np.prod(shape)):
            pixels = np.frombuffer(raw.getbuffer(), np.uint8).reshape(shape)
            software = f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/"
            write_png(path, pixels, DPI, {"Software": software})
            return
    fig.savefig(path, dpi=DPI, format="png", pil_kwargs={"compress_level": 1})


def _colors() -> list[str]:
    import matplotlib

    return matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]


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


class FigureStepsError(InputError):
    """Steps asked for in a figure that the results do not have, or too many of them."""


def default_steps(names: Sequence[str], limit: int = MAX_PANELS) -> list[str]:
    """All step names if there are at most ``limit``, else ``limit`` evenly spread ones,
    the first (the normal load, step A) and the last included."""
    names = list(names)
    if len(names) <= limit:
        return names
    picks = np.unique(np.linspace(0, len(names) - 1, limit).round().astype(int))
    return [names[k] for k in picks]


def _steps(results, steps: Sequence[str] | None) -> list[str]:
    names = [s.name for s in results[0].steps]
    if steps is None:
        return default_steps(names)
    known = set(names)
    missing = [name for name in steps if name not in known]
    if missing or not steps:
        raise FigureStepsError(
            f"figure steps {missing or list(steps)} are not in the results; steps are "
            f"{names[:20]}{' ...' if len(names) > 20 else ''}"
        )
    if len(steps) > MAX_PANELS:
        raise FigureStepsError(
            f"{len(steps)} figure steps asked for; at most {MAX_PANELS} panels are drawn (the "
            "history figure summarises every step): choose fewer"
        )
    return list(steps)


def _history(result: SimulationResult, name: str) -> list[float]:
    """Tangential loads of the steps up to and including ``name``."""
    loads = []
    for s in result.steps:
        loads.append(s.tangential)
        if s.name == name:
            return loads
    raise KeyError(name)


def _grid(n: int, title: str) -> tuple[Figure, list]:
    """n panels, at most 3 per row, on fixed axes rectangles (no empty axes are made),
    sharing both axes (:func:`_outer_labels`)."""
    cols = min(n, 3)
    rows = -(-n // cols)
    height = 3.3 * rows + 1.2
    fig = _figure((4.6 * cols, height))
    grid = fig.add_gridspec(
        rows, cols, left=0.07, right=0.98, top=1 - 0.9 / height, bottom=0.75 / height + 0.05,
        hspace=0.55, wspace=0.25,
    )  # fmt: skip
    fig.suptitle(title)
    axes = _outer_labels(fig, [(grid[k // cols, k % cols], k // cols, k % cols) for k in range(n)])
    for ax in axes:
        ax.locator_params(nbins=TICK_BINS)
    return fig, axes


def _outer_labels(fig: Figure, cells: Sequence, share_y: bool = True) -> list:
    """An axes on each (grid cell, row, column), all sharing one x axis and, if ``share_y``,
    one y axis: one scale to compare the panels by, and the shared axes' tick labels written
    on the outer panels only (the first column's y, the lowest panel of each column's x),
    a third fewer texts to lay out and draw. Each panel keeps its ticks; the caller labels
    the axes whose tick labels are written (:func:`_axis_label`)."""
    lowest = {}
    for _, row, col in cells:
        lowest[col] = max(row, lowest.get(col, row))
    axes = []
    for cell, row, col in cells:
        first = axes[0] if axes else None
        ax = fig.add_subplot(cell, sharex=first, sharey=first if share_y else None)
        ax.tick_params(labelbottom=row == lowest[col], labelleft=col == 0 or not share_y)
        axes.append(ax)
    return axes


def _axis_label(ax, xlabel: str, ylabel: str) -> None:
    """``xlabel`` and ``ylabel`` on the axes of ``ax`` whose tick labels are written."""
    if ax.xaxis.get_tick_params()["labelbottom"]:
        ax.set_xlabel(xlabel)
    if ax.yaxis.get_tick_params()["labelleft"]:
        ax.set_ylabel(ylabel)


def _error_text(
    results, name: str, key: str = "e_q_max", label: str = "max e_q", bases=None
) -> str:
    """A title line with each result's error ``key`` at step ``name`` (empty without theory);
    ``bases``: the results' basis names, if the caller has them."""
    parts = []
    for k, r in enumerate(results):
        errors = r[name].errors
        if errors and errors.get(key) is not None:
            basis = bases[k] if bases is not None else r.describe()["basis"]
            parts.append(f"{basis} {100 * errors[key]:.2f}")
    return f"\n{label} (%): " + ", ".join(parts) if parts else ""


def _step_title(step: StepResult) -> str:
    bulk = step.loads.get("bulk", 0.0) if step.loads else 0.0
    text = f"step {step.name}: P = {step.normal:g}, Q = {step.tangential:g} N/mm"
    return text + (f", $\\sigma_B$ = {bulk:g} MPa" if bulk else "")


def traction_figure(
    results: SimulationResult | Sequence[SimulationResult], steps: Sequence[str] | None = None
) -> Figure:
    """Pressure p and shear q along the contact at each step, with theory (paper Fig. 4)."""
    results = _as_list(results)
    names = _steps(results, steps)
    scale, xlabel = _scale(results)
    ref = _reference(results)
    fig, axes = _grid(len(names), "Contact tractions (traction of the upper body on the lower)")
    colors = _colors()
    labels = [_label(r) for r in results]  # each result described once, not once per line
    bases = [r.describe()["basis"] for r in results]
    for ax, name in zip(axes, names, strict=False):
        for i, r in enumerate(results):
            s, c = r[name], colors[i % len(colors)]
            ax.plot(s.x / scale, s.pressure, "o", ms=3.5, color=c, label=f"p, {labels[i]}")
            ax.plot(s.x / scale, s.shear, "s", ms=3.5, mfc="none", color=c, label=f"q, {labels[i]}")
        if ref is not None:
            span = max(np.abs(r[name].x).max() for r in results)
            fine = np.linspace(-span, span, 801)
            q = ref.shear_traction(fine, _history(results[0], name))
            ax.plot(fine / scale, ref.hertz.pressure(fine), "k-", lw=1, label="p, analytical")
            ax.plot(fine / scale, q, "k--", lw=1, label="q, analytical")
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.set_title(
            _step_title(results[0][name]) + _error_text(results, name, bases=bases), y=TITLE_Y,
            fontsize=TITLE_SIZE,
        )  # fmt: skip
        _axis_label(ax, xlabel, "traction (MPa)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 4), fontsize=LEGEND_SIZE)
    return fig


def displacement_figure(
    results: SimulationResult | Sequence[SimulationResult], steps: Sequence[str] | None = None
) -> Figure:
    """Relative normal (top) and tangential (bottom) displacements along the contact, one
    line per step (colour) and result (marker), with the closed gap -g (paper Fig. 5).

    Two panels hold every step: matplotlib's price is per axes (ticks and labels, about
    30 ms each), not per line, and the steps' curves read best against each other."""
    from matplotlib.lines import Line2D

    results = _as_list(results)
    names = _steps(results, steps)
    scale, xlabel = _scale(results)
    rows = -(-(len(names) + len(results) + 1) // 2)  # legend rows, two columns
    height = 6.6 + 0.22 * rows
    fig = _figure((9.5, height))
    axes = fig.subplots(
        2, 1, sharex=True,
        gridspec_kw={"left": 0.09, "right": 0.98, "top": 1 - 0.55 / height,
                     "bottom": (0.75 + 0.22 * rows) / height, "hspace": 0.08},
    )  # fmt: skip
    fig.suptitle("Relative displacements at the node pairs (upper minus lower body)")
    colors = _colors()
    markers, styles = "osD^v<>", ("-", "--", ":", "-.")
    gap = results[0].simulation.pair.pairing().gap
    own_gaps = any(results[0][name].pair is not None for name in names)  # finite sliding
    fields = (("normal_displacement", "u_n"), ("tangential_displacement", "u_t"))
    handles = []
    for k, name in enumerate(names):
        c = colors[k % len(colors)]
        for i, r in enumerate(results):
            s = r[name]
            for ax, (field, _) in zip(axes, fields, strict=True):
                ax.plot(s.x / scale, 1e3 * getattr(s, field), marker=markers[i % len(markers)],
                        ls=styles[i % len(styles)], ms=3, lw=0.8, mfc="none", color=c)  # fmt: skip
        step = results[0][name]
        if own_gaps:  # each step's own pairing: its gap in the step's colour
            step_gap = gap if step.pair is None else step.pair.pairing().gap
            axes[0].plot(step.x / scale, -1e3 * step_gap, ":", color=c, lw=1.2)
        handles.append(Line2D([], [], color=c, lw=2, label=_step_title(step)))
    if not own_gaps:
        x = results[0][names[0]].x / scale
        axes[0].plot(x, -1e3 * gap, ":", color="0.3", lw=1.2)
    for i, r in enumerate(results):
        style = {"marker": markers[i % len(markers)], "ls": styles[i % len(styles)]}
        handles.append(Line2D([], [], color="0.2", mfc="none", lw=0.8, ms=4, label=_label(r),
                              **style))  # fmt: skip
    gap_label = "−g (gap closed)" + (", per step" if own_gaps else "")
    handles.append(Line2D([], [], color="0.3", ls=":", lw=1.2, label=gap_label))
    for ax, (_, symbol) in zip(axes, fields, strict=True):
        ax.locator_params(nbins=TICK_BINS)
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.grid(alpha=0.3)
        ax.set_ylabel(f"{symbol} (µm)")
    axes[1].set_xlabel(xlabel)
    fig.legend(handles=handles, loc="lower center", ncol=2, fontsize=LEGEND_SIZE)
    return fig


def _edges(x: np.ndarray) -> np.ndarray:
    """Cell edges around sorted centres x (midpoints, ends extended by half a spacing)."""
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def stick_slip_figure(result: SimulationResult | Sequence[SimulationResult]) -> Figure:
    """State of every pair (separated, stick, slip) at every step, with theory's stick zone."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    results = _as_list(result)
    scale, xlabel = _scale(results)
    cols = min(len(results), 3)
    height = 3.6 if len(results[0].steps) <= 12 else 5.0
    fig = _figure((max(7.0, 5.0 * cols), height))
    grid = fig.add_gridspec(
        -(-len(results) // cols), cols, left=0.1, right=0.98, top=0.88, bottom=0.25, wspace=0.3
    )
    cells = [(grid[k // cols, k % cols], k // cols, k % cols) for k in range(len(results))]
    same_steps = len({tuple(s.name for s in r.steps) for r in results}) == 1
    axes = _outer_labels(fig, cells, share_y=same_steps)  # one step axis if one history
    cmap = ListedColormap(STATE_COLORS)
    norm = BoundaryNorm(np.arange(len(STATE_NAMES) + 1) - 0.5, cmap.N)
    for ax, r in zip(axes, results, strict=True):
        states = np.array([s.states for s in r.steps])
        x = r.steps[0].x / scale
        rows = np.arange(len(r.steps) + 1) - 0.5
        few = len(r.steps) <= MAX_STATE_LABELS
        ax.pcolormesh(_edges(x), rows, states, cmap=cmap, norm=norm,
                      edgecolors="w" if few else "face", lw=0.3 if few else 0.0)  # fmt: skip
        ref = r.simulation.reference
        if ref is not None and few:
            a = ref.hertz.half_width / scale
            # [e - c, e + c]: offset by a bulk stress (Nowell-Hills), not mirrored about 0
            zone = np.array(r.theory_stick_zones(), dtype=float) / scale
            rows_k = np.arange(len(zone), dtype=float)
            # every step's two stick-zone ends as the markers of one line artist
            ax.plot(zone.T.ravel(), np.concatenate([rows_k, rows_k]), "k|", ms=14, mew=2)
            ax.axvline(-a, color="k", ls=":", lw=1)
            ax.axvline(a, color="k", ls=":", lw=1)
        shown = default_steps(range(len(r.steps)), MAX_STATE_LABELS)
        ax.set_yticks(shown, [r.steps[k].name[:12] for k in shown])
        ax.locator_params(axis="x", nbins=TICK_BINS)
        if not same_steps or ax is axes[0]:  # shared axes turn together
            ax.invert_yaxis()
        _axis_label(ax, xlabel, "load step")
        ax.set_title(f"pair states, {_label(r)}", y=TITLE_Y)
    handles = [Patch(color=c, label=n) for c, n in zip(STATE_COLORS, STATE_NAMES, strict=True)]
    if _reference(results) is not None:
        label = "analytical stick zone [e − c, e + c]"
        handles.append(Line2D([], [], color="k", marker="|", ls="", ms=10, mew=2, label=label))
        handles.append(Line2D([], [], color="k", ls=":", label="Hertz half-width ±a"))
    ncol = min(len(handles), 5 if cols > 1 else 3)
    fig.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=LEGEND_SIZE)
    return fig


def history_figure(result: SimulationResult | Sequence[SimulationResult]) -> Figure:
    """Summary of a whole history, one point per step: loads, stick-zone width, peak shear."""
    results = _as_list(result)
    fig = _figure((7.0, 6.6))
    axes = fig.subplots(
        3, 1, sharex=True,
        gridspec_kw={"left": 0.12, "right": 0.97, "top": 0.93, "bottom": 0.1, "hspace": 0.12},
    )  # fmt: skip
    fig.suptitle("Load history: one point per step")
    colors = _colors()
    for i, r in enumerate(results):
        steps = np.arange(len(r.steps))
        c = colors[i % len(colors)]
        widths, peaks = [], []
        for s in r.steps:
            stick = s.x[s.states == STATE_NAMES.index("stick")]
            widths.append(float(np.ptp(stick)) if stick.size > 1 else 0.0)
            peaks.append(float(np.max(np.abs(s.shear))) if len(s.shear) else 0.0)
        if i == 0:
            axes[0].plot(steps, [s.normal for s in r.steps], "k-", lw=1, label="P")
            axes[0].plot(steps, [s.tangential for s in r.steps], "k--", lw=1, label="Q")
        axes[1].plot(steps, widths, ".-", ms=3, lw=0.8, color=c, label=_label(r))
        axes[2].plot(steps, peaks, ".-", ms=3, lw=0.8, color=c, label=_label(r))
    axes[0].set_ylabel("load (N/mm)")
    axes[0].legend(fontsize=LEGEND_SIZE)
    axes[1].set_ylabel("stick-zone width (mm)")
    axes[1].legend(fontsize=LEGEND_SIZE)
    axes[2].set_ylabel("peak |q| (MPa)")
    axes[2].set_xlabel("step index (0 = first step)")
    for ax in axes:
        ax.locator_params(nbins=TICK_BINS)
        ax.grid(alpha=0.3)
    return fig


def save_figures(
    result_or_results: SimulationResult | Sequence[SimulationResult],
    directory: str | Path,
    steps: Sequence[str] | None = None,
) -> list[Path]:
    """Write tractions.png, displacements.png, states.png (and history.png for a history of
    more than MAX_PANELS steps) into ``directory``.

    ``steps``: the steps drawn as panels (default: all, or at most MAX_PANELS evenly spread
    ones, the first included, when the history is longer).
    """
    results = _as_list(result_or_results)
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    names = _steps(results, steps)
    makers = {
        "tractions.png": lambda: traction_figure(results, names),
        "displacements.png": lambda: displacement_figure(results, names),
        "states.png": lambda: stick_slip_figure(results),
    }
    if len(results[0].steps) > MAX_PANELS:  # a long history: summarised step by step
        makers["history.png"] = lambda: history_figure(results)
    paths = []
    with _collector_paused(), _text_unhinted():
        for name, make in makers.items():
            fig = make()
            _ticks_in_view(fig)
            try:
                _save_png(fig, directory / name)
            finally:
                _close(fig)
            paths.append(directory / name)
    return paths


# -- geometry ---------------------------------------------------------------------------------
def _axes(ax):
    if ax is None:
        _, ax = _pyplot().subplots(layout="constrained")
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
        points = basis.geometry(*basis.collocation())[0]
        ax.plot(*points.T, ".", color="k", ms=2)
    return ax


@draw.register
def _(obj: ContactPair, ax=None, **style):
    """Both bodies of the pair."""
    ax = _axes(ax)
    draw(obj.upper, ax, **style)
    draw(obj.lower, ax, **style)
    return ax
