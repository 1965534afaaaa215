"""Figures of the convergence study: error against DOFs and time, and the sawtooth.

Drawn from the study's rows with matplotlib's object interface (no pyplot state); matplotlib
is imported only when a figure is drawn.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from .analysis import (
    CALCULIX,
    FIGURES,
    LARGE,
    PAPER_E_Q,
    PAPER_PAIRS,
    TARGET,
    adaptive_series,
    family_label,
    sawtooth_families,
    series,
)

COLORS = ("#4c72b0", "#55a868", "#8172b2", "#dd5544", "#937860", "#da8bc3")
#: (figure, column, x label, whether the larger bodies are drawn: they show the finite-body
#: effect, which the DOFs figure tells; in the time figure they would only crowd it)
AXES = (
    ("dofs", "dofs", "total degrees of freedom (both bodies; adaptive: finest level)", True),
    ("time", "wall_s", "wall time of the five-step cycle, s (median; adaptive: all levels)", False),
)
PANELS = (
    ("e_q_max", "largest shear error, max over steps B-E"),
    ("e_q_l2", "L2 shear error, max over steps B-E"),
)


def _plain(value: float, _=None) -> str:
    return f"{value:g}"


def _sparse(value: float, _=None) -> str:
    """Minor tick labels of a log axis at 2, 3 and 5 times a power of ten only."""
    lead = f"{value:.0e}"[0]
    return f"{value:g}" if lead in "235" else ""


def _log_axes(ax, xlabel: str) -> None:
    """Log-log with plain numbers; on an axis of less than two decades the 2, 3 and 5 times
    a power of ten are labelled too."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis, (low, high) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        axis.set_major_formatter(FuncFormatter(_plain))
        axis.set_minor_formatter(FuncFormatter(_sparse) if high < 100 * low else NullFormatter())
    ax.set_xlabel(xlabel)
    ax.grid(True, which="both", color="0.92", linewidth=0.6)


def _references(ax, axis: str, column: str, scene: dict) -> None:
    """The paper's error (and its star at our nurbs p=2 DOFs) and the CalculiX runs."""
    ax.axhline(100 * PAPER_E_Q, color="k", linewidth=0.8, linestyle="-.")
    ax.annotate(
        f"paper (IGABEM): {100 * PAPER_E_Q:.3f} % at {PAPER_PAIRS} pairs",
        (0.98, 100 * PAPER_E_Q),
        xycoords=("axes fraction", "data"),
        xytext=(0, 3),
        textcoords="offset points",
        fontsize=8,
        ha="right",
    )
    paper_x = [r[column] for r in scene.get(("nurbs", 2), []) if r["pairs"] == PAPER_PAIRS]
    if axis == "dofs" and paper_x:
        ax.plot(paper_x, [100 * PAPER_E_Q], "k*", markersize=12, zorder=5)
    for seconds, _, e_q in CALCULIX if axis == "time" else ():
        ax.plot([seconds], [100 * e_q], "ks", markerfacecolor="none", markersize=7)
        ax.annotate(
            f"CalculiX FE, {seconds:g} s",
            (seconds, 100 * e_q),
            xytext=(-4, 6),
            textcoords="offset points",
            fontsize=8,
            ha="right",
        )


def _lines(key, scene: dict, large: dict, budgets: dict):
    """(runs, legend label, line style) of a family's series that have runs."""
    name = family_label(key)
    lines = (
        (scene.get(key), name, dict(marker="o", linestyle="-", markersize=4, linewidth=1.3)),
        (
            large.get(key),
            f"{name}, bodies x{LARGE:g}",
            dict(marker="^", linestyle="--", markersize=3, linewidth=0.9, alpha=0.6),
        ),
        (
            budgets.get(key),
            f"{name} adaptive (budget)",
            dict(marker="D", linestyle="-", markersize=6, linewidth=2.2, markeredgecolor="k",
                 markeredgewidth=0.6),
        ),
    )  # fmt: skip
    return [line for line in lines if line[0]]


def plot_study(rows: Sequence[dict], out: str | Path, adaptive: Sequence[dict] = ()) -> list[Path]:
    """error_vs_dofs.png and error_vs_time.png: max and L2 e_q over steps B-E, log-log, of
    the fixed-pairs runs (scene's and, against DOFs, larger bodies) and the adaptive series."""
    from matplotlib.figure import Figure  # deferred: the study itself needs no matplotlib

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scene, large, budgets = series(rows, 1.0), series(rows, LARGE), adaptive_series(adaptive)
    keys = sorted(scene | large | budgets)
    color = {key: COLORS[k % len(COLORS)] for k, key in enumerate(keys)}
    paths = []
    for axis, column, xlabel, with_large in AXES:
        fig = Figure(figsize=(11.5, 4.8), layout="constrained")
        panels = fig.subplots(1, 2, sharex=True)
        for ax, (error, title) in zip(panels, PANELS, strict=True):
            for key in keys:
                for data, label, style in _lines(key, scene, large if with_large else {}, budgets):
                    ax.plot(
                        [r[column] for r in data],
                        [100 * r[error] for r in data],
                        color=color[key],
                        label=label,
                        **style,
                    )
            ax.axhline(100 * TARGET, color="0.6", linewidth=0.8, linestyle=":")
            if error == "e_q_max":
                _references(ax, axis, column, scene)
            _log_axes(ax, xlabel)
            ax.set_ylabel("e_q, % of f p0")
            ax.set_title(title, fontsize=10)
        handles, labels = panels[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside right center", fontsize=8)
        path = out / FIGURES[axis]
        fig.savefig(path, dpi=110)
        paths.append(path)
    return paths


def plot_sawtooth(tooth: Sequence[dict], out: str | Path) -> list[Path]:
    """adaptive_study_sawtooth.png: e_q max against pair count, fixed pairs beside the
    adaptive mode at that budget (and its estimate), one panel per family."""
    if not tooth:
        return []
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter, MaxNLocator

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    families = sawtooth_families(tooth)  # in the study's order of families
    fig = Figure(figsize=(11.5, 4.4), layout="constrained")
    panels = fig.subplots(1, len(families), sharey=True, squeeze=False)[0]
    for ax, (key, rows) in zip(panels, families.items(), strict=True):
        pairs = [r["pairs"] for r in rows]
        ax.plot(pairs, [100 * r["fixed_e_q_max"] for r in rows], "-o", color="#dd5544",
                markersize=3, linewidth=1.0, label="fixed pairs = N")  # fmt: skip
        ax.plot(pairs, [100 * r["adaptive_e_q_max"] for r in rows], "-s", color="#4c72b0",
                markersize=3, linewidth=1.6, label="adaptive, budget N")  # fmt: skip
        ax.plot(pairs, [100 * r["estimate_e_q_max"] for r in rows], "--", color="#4c72b0",
                linewidth=0.9, alpha=0.7, label="adaptive estimate")  # fmt: skip
        for level in (0.02, TARGET):
            ax.axhline(100 * level, color="0.5", linewidth=0.8, linestyle=":")
            ax.annotate(f"{100 * level:g} %", (1.0, 100 * level), xycoords=("axes fraction",
                        "data"), xytext=(-3, 2), textcoords="offset points", fontsize=8,
                        ha="right", color="0.4")  # fmt: skip
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(_plain))
        ax.yaxis.set_minor_formatter(FuncFormatter(_sparse))
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_xlabel("N: pairs (fixed) or pair budget (adaptive)")
        ax.set_title(f"{family_label(key)}: e_q max over steps B-E", fontsize=10)
        ax.grid(True, which="both", color="0.92", linewidth=0.6)
    panels[0].set_ylabel("e_q max, % of f p0")
    panels[0].legend(fontsize=8)
    path = out / FIGURES["sawtooth"]
    fig.savefig(path, dpi=110)
    return [path]


__all__ = ["plot_sawtooth", "plot_study"]
