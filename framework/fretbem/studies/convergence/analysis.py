"""Analysis of the convergence study: crossings, fitted exponents, cheapest runs to an error.

Pure functions of the study's rows (``convergence.csv``, ``adaptive_study.csv``,
``adaptive_study_sawtooth.csv``), shared by ``fretbem convergence``, its figures
(:mod:`.convergence_figures`) and the documentation's results page. The external reference
numbers drawn for comparison (the IGABEM paper's error, the CalculiX runs) are read from
``references.toml``, which gives their sources.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from importlib import resources

import numpy as np

from .io import ERRORS

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

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
FIGURES = {
    "dofs": "error_vs_dofs.png",
    "time": "error_vs_time.png",
    "sawtooth": "adaptive_study_sawtooth.png",
}
#: error levels at which the results page names the cheapest run of every series
LEVELS = {"e_q_max": (0.05, 0.02, 0.01), "e_q_l2": (0.01, 0.005, 0.003)}


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


# -- the adaptive mode ----------------------------------------------------------------------
def adaptive_series(adaptive: Sequence[dict]) -> dict[tuple[str, int], list[dict]]:
    """(family, degree) -> its adaptive runs in increasing budget."""
    out: dict[tuple[str, int], list[dict]] = {}
    for row in adaptive:
        out.setdefault((row["family"], row["degree"]), []).append(row)
    return {k: sorted(v, key=lambda r: r["budget"]) for k, v in out.items()}


def series_label(key: tuple) -> str:
    """'nurbs p=2', 'lagrange2', 'nurbs p=2 adaptive' for (family, degree[, mode])."""
    adaptive = len(key) > 2 and key[2] == "adaptive"
    return family_label(key[:2]) + (" adaptive" if adaptive else "")


def all_series(rows: Sequence[dict], adaptive: Sequence[dict] = ()) -> dict[tuple, list[dict]]:
    """(family, degree, mode) -> runs on the scene's bodies, fixed pairs and adaptive."""
    out = {(*k, "fixed"): v for k, v in series(rows).items()}
    out |= {(*k, "adaptive"): v for k, v in adaptive_series(adaptive).items()}
    return out


def cheapest(
    rows: Sequence[dict], adaptive: Sequence[dict], error: str, level: float
) -> dict[tuple, tuple[dict | None, dict | None]]:
    """(family, degree, mode) -> (run with the fewest DOFs, run with the least wall time)
    among those with ``error`` at or below ``level`` (None, None if none is)."""
    out = {}
    for key, runs in all_series(rows, adaptive).items():
        good = [r for r in runs if r[error] <= level]
        out[key] = (
            min(good, key=lambda r: r["dofs"], default=None),
            min(good, key=lambda r: r["wall_s"], default=None),
        )
    return out


def settled_from(tooth: Sequence[dict], column: str, level: float) -> int | None:
    """Smallest pair count from which ``column`` stays at or below ``level`` up to the end of
    the sawtooth (one family's rows); None if its last pair count is above."""
    found = None
    for row in sorted(tooth, key=lambda r: r["pairs"], reverse=True):
        if row[column] > level:
            break
        found = row["pairs"]
    return found


def sawtooth_families(tooth: Sequence[dict]) -> dict[tuple[str, int], list[dict]]:
    """(family, degree) -> its sawtooth rows in increasing pairs."""
    out: dict[tuple[str, int], list[dict]] = {}
    for row in tooth:
        out.setdefault((row["family"], row["degree"]), []).append(row)
    return {k: sorted(v, key=lambda r: r["pairs"]) for k, v in out.items()}
