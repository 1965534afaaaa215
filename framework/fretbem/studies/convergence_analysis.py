"""Analysis and figures of the convergence study: crossings, fitted exponents, log-log plots.

Pure functions of the study's rows (``convergence.csv``), shared by ``fretbem convergence``
and the documentation's results page. The external reference numbers drawn for comparison
(the IGABEM paper's error, the CalculiX runs) are read from ``references.toml``, which
gives their sources.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from importlib import resources
from pathlib import Path

import numpy as np

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ERRORS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
#: the body-size factor of the finite-body comparison
LARGE = 4.0
#: external reference numbers with their sources (studies/references.toml)
REFERENCES = tomllib.loads(
    resources.files(__package__).joinpath("references.toml").read_text(encoding="utf-8")
)
#: largest shear error reported by the IGABEM paper, and at how many pairs
PAPER_PAIRS, PAPER_E_Q = REFERENCES["paper"]["pairs"], REFERENCES["paper"]["e_q_max"]
#: CalculiX on the same scene and error definition: (wall s, DOFs or None, e_q max)
CALCULIX = tuple((c["wall_s"], c.get("dofs"), c["e_q_max"]) for c in REFERENCES["calculix"])
#: the error level the results page asks about
TARGET = 0.01
FIGURES = {"dofs": "error_vs_dofs.png", "time": "error_vs_time.png"}


# -- analysis -----------------------------------------------------------------------------
def main_rows(rows: Sequence[dict], bodies: float = 1.0) -> list[dict]:
    """The convergence runs (rest refinement as in the scene) on bodies of the given size."""
    return [r for r in rows if r["rest"] == 1 and r["bodies"] == bodies]


def series(rows: Sequence[dict], bodies: float = 1.0) -> dict[tuple[str, int], list[dict]]:
    """(family, degree) -> its runs in increasing pairs."""
    out: dict[tuple[str, int], list[dict]] = {}
    for row in main_rows(rows, bodies):
        out.setdefault((row["family"], row["degree"]), []).append(row)
    return {k: sorted(v, key=lambda r: r["pairs"]) for k, v in out.items()}


def family_label(key: tuple[str, int]) -> str:
    family, degree = key
    return f"{family} p={degree}" if family == "nurbs" else family


def fit_exponent(x: Sequence[float], y: Sequence[float]) -> float:
    """Least-squares slope of log y against log x (nan with fewer than two points)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    keep = (x > 0) & (y > 0)
    if keep.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def first_crossing(x: Sequence[float], y: Sequence[float], level: float = TARGET):
    """Smallest x where y first falls to ``level``, interpolated in log-log between levels.

    Returns None if it never does; x[0] if the first level is already below.
    """
    for k, (xk, yk) in enumerate(zip(x, y, strict=True)):
        if yk <= level:
            if k == 0:
                return float(xk)
            x0, y0 = x[k - 1], y[k - 1]
            s = (math.log(level) - math.log(y0)) / (math.log(yk) - math.log(y0))
            return float(math.exp(math.log(x0) + s * (math.log(xk) - math.log(x0))))
    return None


def crossings(rows: Sequence[dict], error: str, bodies: float = 1.0, level: float = TARGET):
    """(family, degree) -> (DOFs, wall s) at which ``error`` first reaches ``level``."""
    out = {}
    for key, runs in series(rows, bodies).items():
        errors = [r[error] for r in runs]
        out[key] = (
            first_crossing([r["dofs"] for r in runs], errors, level),
            first_crossing([r["wall_s"] for r in runs], errors, level),
        )
    return out


def exponents(rows: Sequence[dict], bodies: float = 1.0, min_pairs: int = 0) -> dict:
    """(family, degree) -> slopes of every error (and wall time) against DOFs and pairs,
    fitted over the levels with at least ``min_pairs`` pairs."""
    out = {}
    for key, runs in series(rows, bodies).items():
        runs = [r for r in runs if r["pairs"] >= min_pairs]
        out[key] = {
            **{
                f"{e}_dofs": fit_exponent([r["dofs"] for r in runs], [r[e] for r in runs])
                for e in ERRORS
            },
            **{
                f"{e}_pairs": fit_exponent([r["pairs"] for r in runs], [r[e] for r in runs])
                for e in ERRORS
            },
            "wall_dofs": fit_exponent([r["dofs"] for r in runs], [r["wall_s"] for r in runs]),
        }
    return out


# -- figures ------------------------------------------------------------------------------
def plot_study(rows: Sequence[dict], out: str | Path) -> list[Path]:
    """error_vs_dofs.png and error_vs_time.png: max and L2 e_q over steps B-E, log-log."""
    from matplotlib.figure import Figure  # deferred: the study itself needs no matplotlib
    from matplotlib.ticker import FuncFormatter

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scene, large = series(rows, 1.0), series(rows, LARGE)
    colors = ("#4c72b0", "#55a868", "#8172b2", "#dd5544", "#937860", "#da8bc3")
    paths = []
    for axis, column, label in (
        ("dofs", "dofs", "total degrees of freedom (both bodies)"),
        ("time", "wall_s", "wall time of the five-step cycle, s (median)"),
    ):
        fig = Figure(figsize=(11, 4.6), layout="constrained")
        panels = fig.subplots(1, 2, sharex=True)
        for ax, error, title in (
            (panels[0], "e_q_max", "largest shear error, max over steps B-E"),
            (panels[1], "e_q_l2", "L2 shear error, max over steps B-E"),
        ):
            for k, key in enumerate(sorted(scene | large)):
                color = colors[k % len(colors)]
                for data, style, suffix in (
                    (scene.get(key, []), "-o", ""),
                    (large.get(key, []), "--^", f", bodies x{LARGE:g}"),
                ):
                    if not data:
                        continue
                    ax.plot(
                        [r[column] for r in data],
                        [100 * r[error] for r in data],
                        style,
                        color=color,
                        markersize=4 if not suffix else 3,
                        linewidth=1.5 if not suffix else 1.0,
                        alpha=1.0 if not suffix else 0.7,
                        label=family_label(key) + suffix,
                    )
            ax.axhline(100 * TARGET, color="0.6", linewidth=0.8, linestyle=":")
            if error == "e_q_max":
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
                paper_x = [
                    r[column] for r in scene.get(("nurbs", 2), []) if r["pairs"] == PAPER_PAIRS
                ]
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
            ax.set_xscale("log")
            ax.set_yscale("log")
            plain = FuncFormatter(lambda v, _: f"{v:g}")
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
            ax.set_xlabel(label)
            ax.set_ylabel("e_q, % of f p0")
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="both", color="0.92", linewidth=0.6)
        handles, labels = panels[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside right center", fontsize=8)
        path = out / FIGURES[axis]
        fig.savefig(path, dpi=110)
        paths.append(path)
    return paths
