"""Fretting outputs: loops.csv, slip.csv, the Q-delta loop and slip / energy figures.

Written by the ``fretting`` writer (:mod:`fretbem.output.write`): loops.csv for every run
(one row per increment), slip.csv and the figures when the history has load cycles
(:mod:`fretbem.fretting`); summary.json gets the per-cycle table from :func:`summary`.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from fretbem.fretting.cycles import FrettingAnalysis, analyse

from . import figures as plot
from .staging import csv_cell

#: units and meaning of every loops.csv column
LOOPS_COLUMNS = {
    "increment": ("", "increment number over the whole history (1, 2, ...)"),
    "cycle": ("", "load cycle of the increment (0: outside any cycle, e.g. the normal load)"),
    "Q": ("N/mm", "tangential load carried by the pad's loading block, +x"),
    "delta": (
        "mm",
        "tangential displacement of the pad's loading block against the specimen's held end "
        "(2D displacements need a datum), +x",
    ),
    "P": ("N/mm", "normal load carried by the pad's loading block, > 0 presses"),
    "M": (
        "N mm/mm",
        "moment of the pad's loading block on the pad about the rig's pivot, "
        "counterclockwise > 0 (empty where the pad's model gives none)",
    ),
    "theta": (
        "rad",
        "rotation of the actuator holding the pad's block (the block's plus M / k_r), "
        "counterclockwise > 0",
    ),
    "step": ("", "load step of the increment"),
}
#: units and meaning of every slip.csv column
SLIP_COLUMNS = {
    "cycle": ("", "load cycle"),
    "x": ("mm", "pair position"),
    "slip_amplitude": ("mm", "half the range of the slip (relative tangential displacement)"),
    "energy_density": (
        "N/mm",
        "energy dissipated per unit face area over the cycle (mJ/mm^2): the sum of q ds",
    ),
}
#: units and meaning of every summary.json ``fretting`` key
CYCLE_KEYS = {
    "transition_ratio": (
        "",
        "energy ratio A at the partial / gross slip transition of this scene (null: no Hertz "
        "closed form)",
    ),
    "dissipated_energy": ("N mm/mm", "E_d: energy dissipated in the cycle per mm thickness"),
    "loop_area": (
        "N mm/mm",
        "area of the Q-delta loop (E_d through the block), plus the moment's work M d(theta) "
        "when the pad's block rotates",
    ),
    "delta_amplitude": ("mm", "delta*: half the range of delta over the cycle"),
    "Q_amplitude": ("N/mm", "Q*: half the range of Q over the cycle"),
    "energy_ratio": ("", "A = E_d / (4 delta* Q*)"),
    "regime": ("", "stick, partial slip or gross slip (from the pair states)"),
    "slip_amplitude_max": ("mm", "largest slip amplitude over the face"),
    "caution": ("", "null, or why the cycle is beyond the small-sliding pairing"),
}


def has_cycles(result) -> bool:
    """Whether the history of ``result`` has load cycles."""
    return any(getattr(step, "cycle", 0) for step in result.simulation.steps)


def summary(result) -> dict | None:
    """summary.json's ``fretting`` table, or None for a history without cycles."""
    return analyse(result).summary() if has_cycles(result) else None


def write_loops(analysis: FrettingAnalysis, path: Path) -> Path:
    """loops.csv: one row per increment (see LOOPS_COLUMNS)."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(LOOPS_COLUMNS))
        for k in range(len(analysis.increment)):
            writer.writerow(
                [
                    int(analysis.increment[k]),
                    int(analysis.cycle[k]),
                    repr(float(analysis.tangential[k])),
                    repr(float(analysis.delta[k])),
                    repr(float(analysis.normal[k])),
                    _number(analysis.moment[k] if len(analysis.moment) else float("nan")),
                    repr(float(analysis.rotation[k] if len(analysis.rotation) else 0.0)),
                    csv_cell(analysis.step[k]),
                ]
            )
    return path


def _number(value: float) -> str:
    """A CSV number, empty for NaN (no value)."""
    return repr(float(value)) if np.isfinite(value) else ""


def write_slip(analysis: FrettingAnalysis, path: Path) -> Path:
    """slip.csv: per cycle and pair the slip amplitude and dissipated energy density."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(SLIP_COLUMNS))
        for cycle in analysis.cycles:
            for x, s, w in zip(cycle.x, cycle.slip_amplitude, cycle.energy_density, strict=True):
                writer.writerow([cycle.cycle, repr(float(x)), repr(float(s)), repr(float(w))])
    return path


#: at most this many cycles drawn in the loop figure (evenly spread, first and last kept)
MAX_LOOPS = 6


def _spread(cycles: list, limit: int = MAX_LOOPS) -> list:
    if len(cycles) <= limit:
        return cycles
    picks = np.unique(np.round(np.linspace(0, len(cycles) - 1, limit)).astype(int))
    return [cycles[i] for i in picks]


def initial_stiffness(analysis: FrettingAnalysis) -> float | None:
    """dQ / d(delta) of the first tangential increment (the elastic slope of the loop)."""
    moved = np.flatnonzero(np.abs(np.diff(analysis.delta)) > 0)
    if not moved.size:
        return None
    k = moved[0]
    slope = (analysis.tangential[k + 1] - analysis.tangential[k]) / (
        analysis.delta[k + 1] - analysis.delta[k]
    )
    return float(slope) if np.isfinite(slope) and slope > 0 else None


def loop_figure(analysis: FrettingAnalysis):
    """The Q-delta loops (every cycle, or an even spread of them), with E_d, A and regime;
    beside them the same loops against delta - Q / k0 (k0 the first increment's slope),
    which removes the elastic compliance and leaves the slip's share of delta."""
    fig = plot._figure((11.0, 4.6))
    ax, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    stiffness = initial_stiffness(analysis)
    ax.plot(analysis.delta * 1e3, analysis.tangential, color="#bbbbbb", lw=0.8, label="history")
    colors = plot._colors()
    for k, cycle in enumerate(_spread(list(analysis.cycles))):
        color = colors[k % len(colors)]
        ax.plot(
            cycle.delta * 1e3,
            cycle.tangential,
            color=color,
            lw=1.4,
            label=f"cycle {cycle.cycle}: {cycle.regime}, E_d = {cycle.dissipated_energy:.3g} "
            f"N mm/mm, A = {cycle.energy_ratio:.3g}",
        )
        if stiffness is not None:
            right.plot((cycle.delta - cycle.tangential / stiffness) * 1e3, cycle.tangential,
                       color=color, lw=1.4)  # fmt: skip
    ax.set_xlabel("delta (um): pad block against the specimen's held end")
    ax.set_ylabel("Q (N/mm)")
    for axes in (ax, right):
        axes.axhline(0.0, color="k", lw=0.5)
        axes.axvline(0.0, color="k", lw=0.5)
    title = "Q-delta loops"
    if analysis.transition_ratio is not None:
        title += f" (gross slip at A > {analysis.transition_ratio:.3g})"
    ax.set_title(title, fontsize=10, y=plot.TITLE_Y)
    ax.legend(fontsize=7, loc="lower right")
    if stiffness is not None:
        right.set_xlabel(f"delta - Q / k0 (um), k0 = {stiffness:.4g} N/mm per mm")
        right.set_title("the loops without the elastic slope", fontsize=10, y=plot.TITLE_Y)
    else:
        right.set_axis_off()
    fig.tight_layout()
    return fig


def slip_figure(analysis: FrettingAnalysis):
    """Slip amplitude (top) and dissipated energy density (bottom) along x, per cycle."""
    fig = plot._figure((6.4, 6.0))
    top, bottom = fig.add_subplot(2, 1, 1), fig.add_subplot(2, 1, 2, sharex=None)
    colors = plot._colors()
    for k, cycle in enumerate(_spread(list(analysis.cycles))):
        color = colors[k % len(colors)]
        top.plot(cycle.x, cycle.slip_amplitude * 1e3, "o-", ms=2.5, color=color,
                 label=f"cycle {cycle.cycle}")  # fmt: skip
        bottom.plot(cycle.x, cycle.energy_density, "o-", ms=2.5, color=color)
    top.set_ylabel("slip amplitude (um)")
    bottom.set_ylabel("energy density (N/mm per cycle)")
    bottom.set_xlabel("x (mm)")
    top.legend(fontsize=7)
    top.set_title("slip amplitude and dissipated energy density", fontsize=10, y=plot.TITLE_Y)
    fig.tight_layout()
    return fig


def write_fretting(result, directory: Path, *, figures: bool = True) -> list[Path]:
    """loops.csv for every run; slip.csv, loops.png and slip.png for a history with cycles."""
    analysis = analyse(result)
    paths = [write_loops(analysis, directory / "loops.csv")]
    if not analysis.cycles:
        return paths
    paths.append(write_slip(analysis, directory / "slip.csv"))
    if figures:
        with plot._collector_paused():
            for name, make in (("loops.png", loop_figure), ("slip.png", slip_figure)):
                fig = make(analysis)
                try:
                    fig.savefig(directory / name, dpi=plot.DPI, pil_kwargs={"compress_level": 1})
                finally:
                    plot._close(fig)
                paths.append(directory / name)
    return paths
