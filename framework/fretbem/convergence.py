"""Speed against error: the convergence study of the reference Cattaneo-Mindlin scene.

Every basis family and degree of the study is run on the reference scene
(shared/reference-scene.md) at increasing numbers of node pairs in the candidate contact
zone. Each run records the errors of steps B-E against Mindlin-Deresiewicz theory, the
Newton iterations, the times of assembly, condensation and every step, the wall time and the
peak memory. Two checks go with it:

- *finite bodies*: the scene's bodies are finite (w ~ 20 a) while the theory is for half
  planes, so the same discretisations are also run on bodies four times larger; the
  difference between the two is the finite-body effect, not discretisation error;
- *refinement of the rest*: the flanks, sides and top/bottom are re-run with their element
  counts scaled, and the largest change of the contact tractions is reported.

``run_study`` writes ``convergence.csv`` (one row per run, rewritten after every run),
``study.json`` (machine and plan) and two log-log figures; ``results_page`` turns the CSV
into the markdown results page. Timings are medians over ``repeats`` runs; the peak memory
is the ``tracemalloc`` peak of one separate run (Python and numpy allocations from building
the scene to the last step, not the interpreter's resident size).
"""

from __future__ import annotations

import csv
import gc
import itertools
import json
import math
import os
import platform
import shutil
import statistics
import time
import tracemalloc
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import attrs
import numpy as np

from .scenes import CattaneoMindlinScene, cattaneo_mindlin
from .simulation import run

STEPS = ("A", "B", "C", "D", "E")
#: steps whose errors are reported (A has no shear)
ERROR_STEPS = ("B", "C", "D", "E")
ERRORS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
#: (family, degree) of the study; degree None is the family's default
FAMILIES = (("nurbs", 2), ("nurbs", 3), ("nurbs", 4), ("lagrange2", None))
FULL_PAIRS = (15, 31, 61, 121, 241, 481)
QUICK_PAIRS = (15, 31)
#: the body-size factor of the finite-body comparison
LARGE = 4.0
#: largest shear error reported by the IGABEM paper at 61 pairs (shared/reference/)
PAPER_PAIRS, PAPER_E_Q = 61, 0.04104
#: CalculiX on the same scene and error definition (issue 4): (wall s, DOFs or None, e_q max)
CALCULIX = ((27.0, None, 0.11), (720.0, 89_000, 0.057))
#: the error level the results page asks about
TARGET = 0.01
CSV_NAME, META_NAME = "convergence.csv", "study.json"
FIGURES = {"dofs": "error_vs_dofs.png", "time": "error_vs_time.png"}

COLUMNS = (
    "family",
    "degree",
    "pairs",
    "bodies",
    "width",
    "height",
    "rest",
    "flank_elements",
    "side_elements",
    "top_elements",
    "dofs",
    *(f"{e}_{s}" for e in ERRORS for s in ERROR_STEPS),
    *ERRORS,
    *(f"iterations_{s}" for s in STEPS),
    "iterations",
    "assembly_s",
    "factorisation_s",
    "condensation_s",
    *(f"solve_{s}_s" for s in STEPS),
    "steps_s",
    "run_s",
    "wall_s",
    "peak_memory_mib",
    "repeats",
    "rest_change_p",
    "rest_change_q",
)


@attrs.frozen
class Case:
    """One run of the study.

    Attributes
    ----------
    family : str
    degree : int or None
        None for the family's default.
    pairs : int
    bodies : float
        Size of both bodies over the scene's (width and height scaled; 1 = the scene).
    rest : float
        Factor on the element counts of flanks, sides and top/bottom (1 = the scene's).
    """

    family: str
    degree: int | None
    pairs: int
    bodies: float = 1.0
    rest: float = 1.0

    def scene(self) -> CattaneoMindlinScene:
        base = CattaneoMindlinScene()
        count = lambda n: max(1, round(n * self.rest))  # noqa: E731
        return attrs.evolve(
            base,
            basis=self.family,
            degree=self.degree,
            pairs=self.pairs,
            width=base.width * self.bodies,
            height=base.height * self.bodies,
            flank_elements=count(base.flank_elements),
            side_elements=count(base.side_elements),
            top_elements=count(base.top_elements),
        )

    @property
    def baseline(self) -> Case:
        """The same run with the scene's refinement of the rest."""
        return attrs.evolve(self, rest=1.0)

    def label(self) -> str:
        degree = "" if self.degree is None else f" p={self.degree}"
        extra = "" if self.bodies == 1 else f", bodies x{self.bodies:g}"
        extra += "" if self.rest == 1 else f", rest x{self.rest:g}"
        return f"{self.family}{degree}, {self.pairs} pairs{extra}"


@attrs.frozen
class StudyPlan:
    """Which runs make the study.

    Attributes
    ----------
    families : tuple of (family, degree)
    pairs : tuple of int
        Levels on the scene's bodies.
    large_pairs : tuple of int
        Levels also run on bodies ``LARGE`` times larger (finite-body comparison).
    rest_pairs : tuple of int
        Levels at which the refinement of the rest is checked.
    rest_factors : tuple of float
        Factors on the element counts of flanks, sides and top/bottom for that check.
    check_families : tuple of (family, degree) or None
        Families of the finite-body and rest checks (None: all ``families``).
    repeats : int
        Timed runs per case (timings are their medians).
    memory : bool
        Measure the tracemalloc peak in one extra run per case.
    """

    families: tuple[tuple[str, int | None], ...] = FAMILIES
    pairs: tuple[int, ...] = FULL_PAIRS
    large_pairs: tuple[int, ...] = FULL_PAIRS
    rest_pairs: tuple[int, ...] = (61, 481)
    rest_factors: tuple[float, ...] = (0.5, 2.0, 4.0)
    check_families: tuple[tuple[str, int | None], ...] | None = None
    repeats: int = 3
    memory: bool = True

    @classmethod
    def full(cls) -> StudyPlan:
        return cls()

    @classmethod
    def quick(cls) -> StudyPlan:
        """A few small levels for CI: every family at 15 and 31 pairs; checks at 31 pairs
        for nurbs p=2 and lagrange2."""
        return cls(
            pairs=QUICK_PAIRS,
            large_pairs=QUICK_PAIRS[-1:],
            rest_pairs=QUICK_PAIRS[-1:],
            rest_factors=(2.0,),
            check_families=(("nurbs", 2), ("lagrange2", None)),
            repeats=1,
        )

    def cases(self) -> list[Case]:
        """Scene bodies first, then the larger bodies, then the refinement checks."""
        checked = self.families if self.check_families is None else self.check_families
        out = [Case(f, d, n) for f, d in self.families for n in self.pairs]
        out += [Case(f, d, n, bodies=LARGE) for f, d in checked for n in self.large_pairs]
        out += [
            Case(f, d, n, rest=r)
            for f, d in checked
            for n in self.rest_pairs
            for r in self.rest_factors
        ]
        return out


def _median(values: Iterable[float]) -> float:
    return float(statistics.median(list(values)))


def measure(case: Case, repeats: int = 1, memory: bool = True):
    """Run ``case``; returns (row without the rest-change columns, result of the first run).

    Wall time is from building the scene to the last step; every timing is the median over
    ``repeats`` runs. With ``memory`` one more run is traced with tracemalloc.
    """
    walls, timings, first = [], [], None
    for _ in range(max(1, repeats)):
        gc.collect()
        tic = time.perf_counter()
        result = run(cattaneo_mindlin(case.scene()))
        walls.append(time.perf_counter() - tic)
        timings.append({**result.timings, **{f"solve_{s.name}": s.seconds for s in result.steps}})
        if first is None:
            first = result
    peak = math.nan
    if memory:
        gc.collect()
        tracemalloc.start()
        try:
            run(cattaneo_mindlin(case.scene()))
            peak = tracemalloc.get_traced_memory()[1] / 2**20
        finally:
            tracemalloc.stop()
    scene = case.scene()
    info = first.describe()
    steps = {s.name: s for s in first.steps}
    row: dict[str, object] = {
        "family": case.family,
        "degree": info["degree"],
        "pairs": info["pairs"],
        "bodies": case.bodies,
        "width": scene.width,
        "height": scene.height,
        "rest": case.rest,
        "flank_elements": scene.flank_elements,
        "side_elements": scene.side_elements,
        "top_elements": scene.top_elements,
        "dofs": info["dofs"],
    }
    for error in ERRORS:
        for name in ERROR_STEPS:
            row[f"{error}_{name}"] = steps[name].errors[error]
        row[error] = max(steps[name].errors[error] for name in ERROR_STEPS)
    for name in STEPS:
        row[f"iterations_{name}"] = steps[name].iterations
    row["iterations"] = sum(s.iterations for s in first.steps)
    median = lambda key: _median(t[key] for t in timings)  # noqa: E731
    row["assembly_s"] = median("assembly")
    row["factorisation_s"] = median("factorisation")
    row["condensation_s"] = median("condensation")  # includes the factorisation
    for name in STEPS:
        row[f"solve_{name}_s"] = median(f"solve_{name}")
    row["steps_s"] = median("steps")
    row["run_s"] = median("total")
    row["wall_s"] = _median(walls)
    row["peak_memory_mib"] = peak
    row["repeats"] = max(1, repeats)
    return row, first


def tractions(result) -> tuple[float, float, list[tuple[np.ndarray, ...]]]:
    """p0, f p0 and per step the pair positions, p and q: what traction_change compares."""
    reference = result.simulation.reference
    p0 = reference.hertz.peak_pressure
    return p0, reference.friction * p0, [(s.x, s.pressure, s.shear) for s in result.steps]


def traction_change(result, baseline) -> tuple[float, float]:
    """Largest change of p (over p0) and of q (over f p0) at any pair and step.

    ``result`` and ``baseline`` are SimulationResults or ``tractions`` of them.
    """
    (_, _, ours), (p0, fp0, theirs) = (
        r if isinstance(r, tuple) else tractions(r) for r in (result, baseline)
    )
    dp = dq = 0.0
    for (xa, pa, qa), (xb, pb, qb) in zip(ours, theirs, strict=True):
        if xa.shape != xb.shape or not np.allclose(xa, xb, rtol=0, atol=1e-9):
            raise ValueError("traction_change needs runs with the same contact pairs")
        dp = max(dp, float(np.max(np.abs(pa - pb))) / p0)
        dq = max(dq, float(np.max(np.abs(qa - qb))) / fp0)
    return dp, dq


def machine() -> dict:
    """Cores, platform and versions, for the record."""
    import scipy

    threads = {
        k: os.environ[k]
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
        if k in os.environ
    }
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    return {
        "cores": os.cpu_count(),
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "blas_threads_env": threads,
        "load_average_1min": load,
    }


# -- CSV ----------------------------------------------------------------------------------
def write_csv(rows: Sequence[dict], path: str | Path) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _format(row.get(k)) for k in COLUMNS})


def _format(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


_TEXT = {"family"}
_INT = {"degree", "pairs", "dofs", "repeats", "iterations", "flank_elements"}
_INT |= {"side_elements", "top_elements"} | {f"iterations_{s}" for s in STEPS}


def read_csv(path: str | Path) -> list[dict]:
    """Rows of a study CSV with numbers parsed (empty cells are None)."""
    rows = []
    with open(path, newline="") as handle:
        for raw in csv.DictReader(handle):
            row = {}
            for key, value in raw.items():
                if key in _TEXT:
                    row[key] = value
                elif value in ("", None):
                    row[key] = None
                elif key in _INT:
                    row[key] = int(value)
                else:
                    row[key] = float(value)
            rows.append(row)
    return rows


# -- the study ----------------------------------------------------------------------------
def run_study(
    plan: StudyPlan | None = None,
    out: str | Path = "convergence-out",
    *,
    figures: bool = True,
    progress: Callable[[str], None] | None = print,
) -> list[dict]:
    """Run every case of ``plan``; writes the CSV after each run, then study.json, figures."""
    plan = plan or StudyPlan.full()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda message: None)
    meta = {"plan": attrs.asdict(plan), "machine": machine(), "started": time.ctime()}
    start = time.perf_counter()
    rows, baselines = [], {}
    cases = plan.cases()
    needed = {c.baseline for c in cases if c.rest != 1}
    say(
        f"convergence study: {len(cases)} runs, {plan.repeats} timed repeat(s) each, "
        f"{os.cpu_count()} cores; writing {out / CSV_NAME}"
    )
    for k, case in enumerate(cases, 1):
        row, result = measure(case, plan.repeats, plan.memory)
        row["rest_change_p"] = row["rest_change_q"] = None
        if case in needed:
            baselines[case] = tractions(result)
        if case.rest != 1:
            if case.baseline not in baselines:
                baselines[case.baseline] = tractions(run(cattaneo_mindlin(case.baseline.scene())))
            change = traction_change(result, baselines[case.baseline])
            row["rest_change_p"], row["rest_change_q"] = change
        rows.append(row)
        write_csv(rows, out / CSV_NAME)
        say(
            f"[{k:3d}/{len(cases)}] {case.label():<38} {row['dofs']:5d} DOFs  "
            f"e_q max {100 * row['e_q_max']:6.3f} %  L2 {100 * row['e_q_l2']:6.3f} %  "
            f"wall {row['wall_s']:6.2f} s  peak {row['peak_memory_mib']:7.1f} MiB"
        )
        del result
    meta["seconds"] = time.perf_counter() - start
    meta["machine_after"] = {"load_average_1min": machine()["load_average_1min"]}
    (out / META_NAME).write_text(json.dumps(meta, indent=2))
    if figures:
        paths = plot_study(rows, out)
        say(f"wrote {', '.join(str(p) for p in paths)}")
    say(f"study done in {meta['seconds']:.1f} s")
    return rows


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


# -- results page -------------------------------------------------------------------------
def _pct(value, digits: int = 3) -> str:
    return "–" if value is None else f"{100 * value:.{digits}f}"


def _seconds(value) -> str:
    if value is None:
        return "–"
    return f"{value:.3f}" if value < 10 else f"{value:.1f}"


def _mib(value) -> str:
    return "–" if value is None or math.isnan(value) else f"{value:.0f}"


def _describe_crossing(cross: dict, what: str) -> str:
    """A sentence on which family reaches the target first, in DOFs and in wall time."""
    reached = {k: v for k, v in cross.items() if v[0] is not None}
    if not reached:
        return f"No family reaches {100 * TARGET:g} % in {what} at the levels run."
    by_dofs = sorted(reached.items(), key=lambda kv: kv[1][0])
    by_time = sorted(
        ((k, v) for k, v in reached.items() if v[1] is not None), key=lambda kv: kv[1][1]
    )
    text = (
        f"In {what}, {family_label(by_dofs[0][0])} reaches {100 * TARGET:g} % first in "
        f"degrees of freedom (at about {by_dofs[0][1][0]:.0f} DOFs"
    )
    others = [f"{family_label(k)} {v[0]:.0f}" for k, v in by_dofs[1:]]
    text += f"; then {', '.join(others)})" if others else ")"
    if by_time:
        text += (
            f" and {family_label(by_time[0][0])} first in wall time (about {by_time[0][1][1]:.2f} s"
        )
        others = [f"{family_label(k)} {v[1]:.2f} s" for k, v in by_time[1:]]
        text += f"; then {', '.join(others)})" if others else ")"
    missing = [family_label(k) for k, v in cross.items() if v[0] is None]
    if missing:
        text += f"; {', '.join(missing)} never get{'s' if len(missing) == 1 else ''} there"
    return text + "."


def results_page(
    rows: Sequence[dict],
    *,
    meta: dict | None = None,
    figures: dict[str, str] | None = None,
    benchmarks: Sequence[dict] | None = None,
) -> str:
    """The markdown results page, every number computed from the study's rows."""
    figures = figures or FIGURES
    lines = [
        "# Results: speed against error",
        "",
        "<!-- generated by benchmarks/results_page.py from the convergence study's CSV; "
        "do not edit by hand -->",
        "",
        "The reference Cattaneo–Mindlin fretting cycle (`shared/reference-scene.md`) run by "
        "`fretbem convergence` for every basis family and degree at increasing numbers of node "
        "pairs in the candidate contact zone. Errors are those of the scene definition: "
        "e_p = |p − p_exact| / p0, e_q = |q − q_exact| / (f p0), largest over the pairs (max) "
        "or root mean square over the zone (L2), and here the largest over steps B–E. Times "
        "are medians of repeated runs; *wall* is building the scene, assembling, condensing "
        "and the five steps.",
        "",
    ]
    if meta:
        m = meta.get("machine", {})
        plan = meta.get("plan", {})
        lines += [
            f"Machine: {m.get('cores')} cores, {m.get('processor')}, {m.get('platform')}; "
            f"Python {m.get('python')}, numpy {m.get('numpy')}, scipy {m.get('scipy')}"
            + f"; {_threads(m)}"
            + f". {plan.get('repeats', '?')} timed runs per case; the study took "
            f"{meta.get('seconds', math.nan):.0f} s.",
            "",
        ]
    lines += _speed_paragraph(rows)
    lines += [
        f"![error against degrees of freedom]({figures['dofs']})",
        "",
        f"![error against wall time]({figures['time']})",
        "",
        "Solid lines: the scene's bodies; dashed: the same discretisations on bodies "
        f"{LARGE:g}× larger. Dash-dotted: the paper's {100 * PAPER_E_Q:.3f} % at "
        f"{PAPER_PAIRS} pairs (star: at the DOFs of our nurbs p=2 run with {PAPER_PAIRS} pairs; "
        "the paper gives no timing). Squares: the CalculiX finite element model quoted in the "
        "issue (27 s at 61 contact nodes; 720 s with 301 nodes and 89 000 DOFs). "
        f"Dotted: {100 * TARGET:g} %.",
        "",
    ]
    lines += _main_table(rows)
    lines += _step_tables(rows)
    lines += _finite_body_section(rows)
    lines += _rest_section(rows)
    lines += _exponent_section(rows)
    if benchmarks:
        lines += _benchmark_section(benchmarks)
    return "\n".join(lines).rstrip() + "\n"


def _speed_paragraph(rows) -> list[str]:
    out = ["## Which family is fastest to 1 %", ""]
    sentences = []
    for bodies, where in ((1.0, "on the scene's bodies"), (LARGE, f"on bodies {LARGE:g}× larger")):
        if not main_rows(rows, bodies):
            continue
        for error, name in (
            ("e_q_max", "the largest shear error"),
            ("e_q_l2", "the L2 shear error"),
        ):
            sentences.append(_describe_crossing(crossings(rows, error, bodies), f"{name} {where}"))
    out += [" ".join(sentences), ""]
    scene_max, large_max = crossings(rows, "e_q_max", 1.0), crossings(rows, "e_q_max", LARGE)
    lucky = [
        family_label(k)
        for k, v in scene_max.items()
        if v[0] is not None and k in large_max and large_max[k][0] is None
    ]
    if lucky and main_rows(rows, LARGE):
        out += [
            f"{', '.join(lucky)} reach{'es' if len(lucky) == 1 else ''} "
            f"{100 * TARGET:g} % in the largest shear error on the scene's bodies but not on "
            "the larger bodies at the same discretisation: there the finite-body error and "
            "the discretisation error partly cancel at the worst node, so that crossing is "
            "not a convergence result.",
            "",
        ]
    out += _crossing_table(rows)
    scene = main_rows(rows, 1.0)
    at_paper = [r for r in scene if r["pairs"] == PAPER_PAIRS]
    if at_paper:
        best = min(at_paper, key=lambda r: r["e_q_max"])
        out += [
            f"At the paper's {PAPER_PAIRS} pairs the largest shear error is "
            + ", ".join(
                f"{_pct(r['e_q_max'])} % ({family_label((r['family'], r['degree']))}, "
                f"{r['wall_s']:.2f} s)"
                for r in sorted(at_paper, key=lambda r: (r["family"] != "nurbs", r["degree"]))
            )
            + f" against the paper's {100 * PAPER_E_Q:.3f} %; the best, "
            f"{family_label((best['family'], best['degree']))}, is "
            f"{'below' if best['e_q_max'] < PAPER_E_Q else 'above'} it.",
            "",
        ]
    if scene:
        fastest = min(
            (r for r in scene if r["e_q_max"] <= CALCULIX[0][2]),
            key=lambda r: r["wall_s"],
            default=None,
        )
        best = min(scene, key=lambda r: r["e_q_max"])
        if fastest is not None:
            out += [
                f"For comparison, CalculiX needed {CALCULIX[0][0]:g} s for "
                f"{_pct(CALCULIX[0][2], 0)} % and {CALCULIX[1][0]:g} s for "
                f"{_pct(CALCULIX[1][2], 1)} %; the fastest fretbem run at or below "
                f"{_pct(CALCULIX[0][2], 0)} % took {fastest['wall_s']:.2f} s "
                f"({family_label((fastest['family'], fastest['degree']))}, {fastest['pairs']} "
                f"pairs, {_pct(fastest['e_q_max'])} %), and the most accurate run "
                f"({family_label((best['family'], best['degree']))}, {best['pairs']} pairs, "
                f"{_pct(best['e_q_max'])} %) {best['wall_s']:.2f} s.",
                "",
            ]
    return out


def _crossing_table(rows) -> list[str]:
    """DOFs and wall time at which each family first reaches TARGET, per error and bodies."""
    columns = [
        (error, bodies)
        for bodies in (1.0, LARGE)
        if main_rows(rows, bodies)
        for error in ("e_q_max", "e_q_l2")
    ]
    if not columns:
        return []
    found = {c: crossings(rows, *c) for c in columns}
    head = " | ".join(
        f"{'max' if e == 'e_q_max' else 'L2'} e_q, bodies ×{b:g}: DOFs / s" for e, b in columns
    )
    out = [
        f"First reaching {100 * TARGET:g} % (log-log interpolation between levels; – never):",
        "",
        f"| family | {head} |",
        "|---|" + "---:|" * len(columns),
    ]
    for key in sorted(series(rows, 1.0) | series(rows, LARGE)):
        cells = []
        for column in columns:
            dofs, wall = found[column].get(key, (None, None))
            cells.append("–" if dofs is None else f"{dofs:.0f} / {wall:.2f}")
        out.append(f"| {family_label(key)} | " + " | ".join(cells) + " |")
    return [*out, ""]


def _iterations(row) -> str:
    return "/".join(str(row[f"iterations_{s}"]) for s in STEPS)


def _main_table(rows) -> list[str]:
    out = [
        "## All runs on the scene's bodies",
        "",
        "Errors in % (largest over steps B–E); iterations per step A/B/C/D/E; times in s "
        "(condense includes the LU factorisation; solve is the mean per step); memory is the "
        "tracemalloc peak of one run in MiB.",
        "",
        "| family | p | pairs | DOFs | e_p max | e_q max | e_p L2 | e_q L2 | iterations "
        "| assembly | condense | solve/step | wall | memory |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|",
    ]
    for key, runs in sorted(series(rows, 1.0).items()):
        for r in runs:
            out.append(
                f"| {key[0]} | {key[1]} | {r['pairs']} | {r['dofs']} | {_pct(r['e_p_max'])} | "
                f"{_pct(r['e_q_max'])} | {_pct(r['e_p_l2'])} | {_pct(r['e_q_l2'])} | "
                f"{_iterations(r)} | {_seconds(r['assembly_s'])} | "
                f"{_seconds(r['condensation_s'])} | {_seconds(r['steps_s'] / len(STEPS))} | "
                f"{_seconds(r['wall_s'])} | {_mib(r['peak_memory_mib'])} |"
            )
    return [*out, ""]


def _step_tables(rows) -> list[str]:
    out = ["### Errors per step (scene's bodies, %)", ""]
    for errors in (("e_q_max", "e_q_l2"), ("e_p_max", "e_p_l2")):
        header = "| family | p | pairs | " + " | ".join(
            f"{e[:3]} {e[4:]} {s}" for e in errors for s in ERROR_STEPS
        )
        out += [header + " |", "|---|---:|---:|" + "---:|" * (2 * len(ERROR_STEPS))]
        for key, runs in sorted(series(rows, 1.0).items()):
            for r in runs:
                cells = [_pct(r[f"{e}_{s}"]) for e in errors for s in ERROR_STEPS]
                out.append(f"| {key[0]} | {key[1]} | {r['pairs']} | " + " | ".join(cells) + " |")
        out.append("")
    return out


def _finite_body_section(rows) -> list[str]:
    large = series(rows, LARGE)
    if not large:
        return []
    scene = series(rows, 1.0)
    out = [
        "## Finite bodies against half-plane theory",
        "",
        f"The scene's bodies are {CattaneoMindlinScene().width:g} mm wide, about 20 contact "
        "half-widths; the theory is for half-planes. The same discretisations on bodies "
        f"{LARGE:g}× larger (width {LARGE * CattaneoMindlinScene().width:g} mm, height "
        f"{LARGE * CattaneoMindlinScene().height:g} mm) separate the finite-body effect from "
        "the discretisation error. Errors in % (largest over steps B–E), scene → larger.",
        "",
        "| family | p | pairs | e_p max | e_p L2 | e_q max | e_q L2 |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for key, runs in sorted(large.items()):
        base = {r["pairs"]: r for r in scene.get(key, [])}
        for r in runs:
            b = base.get(r["pairs"])
            cells = [
                f"{_pct(b[e]) if b else '–'} → {_pct(r[e])}"
                for e in ("e_p_max", "e_p_l2", "e_q_max", "e_q_l2")
            ]
            out.append(f"| {key[0]} | {key[1]} | {r['pairs']} | " + " | ".join(cells) + " |")
    finest = [
        (key, runs[-1], {r["pairs"]: r for r in scene.get(key, [])}.get(runs[-1]["pairs"]))
        for key, runs in large.items()
    ]
    finest = [(k, r, b) for k, r, b in finest if b is not None]
    if finest:
        dl2 = [b["e_p_l2"] - r["e_p_l2"] for _, r, b in finest]
        dmax = [b["e_p_max"] - r["e_p_max"] for _, r, b in finest]
        out += [
            "",
            f"At the finest level ({finest[0][1]['pairs']} pairs) the L2 pressure error is "
            + ", ".join(
                f"{_pct(b['e_p_l2'])} → {_pct(r['e_p_l2'])} % ({family_label(k)})"
                for k, r, b in sorted(finest)
            )
            + f" on the scene's → larger bodies (a difference of {_pct(min(dl2), 2)} to "
            f"{_pct(max(dl2), 2)} % of p0), and the largest pressure error changes by "
            f"{_pct(min(dmax), 2)} to {_pct(max(dmax), 2)} % of p0. The part of the scene's "
            "error that enlarging the bodies removes is the finite-body effect, which no "
            "refinement of the contact zone removes. The largest errors sit at the contact "
            "edges and stick–slip boundaries, where the exact traction has a square-root or "
            "kink singularity, and need not fall monotonically with refinement.",
        ]
    out += ["", _monotonic_sentence(rows)]
    return [*out, ""]


def _falls(values: Sequence[float]) -> bool:
    return all(b < a for a, b in itertools.pairwise(values))


def _monotonic_sentence(rows) -> str:
    """Which error series fall at every level, from 31 pairs on, per body size."""
    parts = []
    for bodies, where in ((1.0, "the scene's bodies"), (LARGE, f"the {LARGE:g}× bodies")):
        runs = {k: [r for r in v if r["pairs"] >= 31] for k, v in series(rows, bodies).items()}
        runs = {k: v for k, v in runs.items() if len(v) >= 3}
        if not runs:
            continue
        for error in ("e_q_l2", "e_q_max"):
            falling = [
                family_label(k) for k, v in sorted(runs.items()) if _falls([r[error] for r in v])
            ]
            name = "L2" if error == "e_q_l2" else "largest"
            parts.append(
                f"on {where} the {name} shear error falls at every level from 31 pairs for "
                + (", ".join(falling) if falling else "no family")
                + f" (of {len(runs)})"
            )
    return ("Monotonic convergence: " + "; ".join(parts) + ".") if parts else ""


def _factors(rows) -> str:
    return ", ".join(f"×{f:g}" for f in sorted({r["rest"] for r in rows}))


def _rest_section(rows) -> list[str]:
    checks = [r for r in rows if r["rest"] != 1]
    if not checks:
        return []
    out = [
        "## Refinement of the rest of the bodies",
        "",
        "The contact zone is kept; the element counts of the flanks, sides and top/bottom "
        "(scene: 16, 12, 12 per body) are scaled. Change of the tractions at any pair and step "
        "against the scene's refinement, in % of p0 (pressure) and of f p0 (shear):",
        "",
        "| family | p | pairs | rest × | DOFs | change p | change q | e_q max | e_q L2 |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in sorted(checks, key=lambda r: (r["family"], r["degree"], r["pairs"], r["rest"])):
        out.append(
            f"| {r['family']} | {r['degree']} | {r['pairs']} | {r['rest']:g} | {r['dofs']} | "
            f"{_pct(r['rest_change_p'], 4)} | {_pct(r['rest_change_q'], 4)} | "
            f"{_pct(r['e_q_max'])} | {_pct(r['e_q_l2'])} |"
        )
    finer = [r for r in checks if r["rest"] > 1]
    coarser = [r for r in checks if r["rest"] < 1]
    if finer:
        worst = max(max(r["rest_change_p"], r["rest_change_q"]) for r in finer)
        out += [
            "",
            f"Refining the rest further ({_factors(finer)}) "
            f"changes no traction by more than {_pct(worst, 3)} % of p0 (or f p0)",
        ]
        if coarser:
            worst_c = max(max(r["rest_change_p"], r["rest_change_q"]) for r in coarser)
            out[-1] += (
                f"; coarsening it ({_factors(coarser)}) changes them by up to {_pct(worst_c, 3)} %"
            )
        out[-1] += "."
    return [*out, ""]


def _exponent_section(rows) -> list[str]:
    out = [
        "## Fitted exponents",
        "",
        "Least-squares slopes of log(error) against log(pairs) (the zone's element size is "
        "2 × 1.5 a / pairs), over all levels and, in brackets, from 61 pairs on; negative is "
        "converging. The max errors are dominated by single nodes at the contact edges and "
        "stick–slip boundaries, so their slopes are rough. The last two columns are slopes "
        "against DOFs: of the L2 shear error (from 61 pairs on) and of the wall time.",
        "",
        "| bodies | family | p | e_p max | e_q max | e_p L2 | e_q L2 | e_q L2 vs DOFs "
        "| wall vs DOFs |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for bodies in (1.0, LARGE):
        tails = exponents(rows, bodies, min_pairs=PAPER_PAIRS)
        for key, fit in sorted(exponents(rows, bodies).items()):
            if math.isnan(fit["e_q_l2_pairs"]):
                continue
            tail = tails.get(key, {})
            cells = [
                f"{fit[f'{e}_pairs']:.2f} ({tail.get(f'{e}_pairs', math.nan):.2f})" for e in ERRORS
            ]
            out.append(
                f"| ×{bodies:g} | {key[0]} | {key[1]} | "
                + " | ".join(cells)
                + f" | {tail.get('e_q_l2_dofs', math.nan):.2f} | {fit['wall_dofs']:.2f} |"
            )
    return [*out, ""]


def _benchmark_section(runs: Sequence[dict]) -> list[str]:
    """Benchmark medians of one or more ``benchmarks/performance.py --json`` files."""
    runs = [runs] if isinstance(runs, dict) else list(runs)
    out = ["## Performance budget", ""]
    m = runs[0].get("machine", {})
    out += [
        f"`benchmarks/performance.py` on {m.get('cores')} cores, {m.get('processor')}, "
        f"Python {m.get('python')}, numpy {m.get('numpy')}; medians of at least 5 runs. "
        "Columns: the BLAS thread setting and the machine's 1-minute load average at the start "
        "(the machine was shared).",
        "",
    ]
    labels = [
        f"{_threads(r['machine'])}, load {r['machine'].get('load_average_1min', math.nan):.1f}"
        for r in runs
    ]
    out += [
        "| benchmark | target | " + " | ".join(labels) + " |",
        "|---|---:|" + "---:|" * len(runs),
    ]
    order: dict[str, dict] = {}
    for r in runs:
        for item in r.get("results", []):
            order.setdefault(item["key"], item)
    for key, first in order.items():
        unit = first.get("unit", "s")
        target = first.get("target")
        cells = []
        for r in runs:
            item = next((i for i in r.get("results", []) if i["key"] == key), None)
            if item is None:
                cells.append("–")
                continue
            verdict = ""
            if target is not None:
                verdict = " ✓" if item["median"] <= target else " **missed**"
            value = f"{item['median']:.0f}" if unit == "MiB" else f"{item['median']:.3g}"
            cells.append(f"{value} {unit}{verdict}")
        out.append(
            f"| {first['name']} | {'–' if target is None else f'≤ {target:g} {unit}'} | "
            + " | ".join(cells)
            + " |"
        )
    for key, first in order.items():
        target = first.get("target")
        if target is None:
            continue
        missed = [
            label
            for label, r in zip(labels, runs, strict=True)
            for item in r.get("results", [])
            if item["key"] == key and item["median"] > target
        ]
        if missed:
            out += ["", f"Target missed: {first['name']} with {'; '.join(missed)}."]
    if len({_threads(r["machine"]) for r in runs}) > 1:
        out += [
            "",
            "The columns differ in the BLAS thread setting. With OpenBLAS's default (one "
            "thread per core) every dense solve of the Newton iteration is split across both "
            "cores; when another process occupies one of them, each call waits for the "
            "descheduled helper thread, and the small solves of the contact iteration become "
            "one to two orders of magnitude slower. One BLAS thread avoids that at little "
            "cost for these matrix sizes.",
        ]
    for r in runs:
        for item in r.get("results", []):
            if item["key"] == "assembly_largest" and "series" in item:
                sizes = ", ".join(
                    f"{p['dofs']} DOFs {statistics.median(p['times']):.3g} s"
                    for p in item["series"]
                )
                out += [
                    "",
                    f"Assembly of one body ({_threads(r['machine'])}): {sizes}; fitted exponent "
                    f"{item['exponent']:.2f} over all sizes, {item['exponent_upper_half']:.2f} "
                    "over the upper half.",
                ]
            if item["key"] == "step_481" and "series" in item:
                sizes = ", ".join(
                    f"{p['pairs']} pairs {1e3 * statistics.median(p['times']):.3g} ms"
                    for p in item["series"]
                )
                out += [
                    "",
                    f"One load step on the condensed problem ({_threads(r['machine'])}): {sizes}; "
                    f"fitted exponent {item['exponent']:.2f} against pairs.",
                ]
    return [*out, ""]


def _threads(m: dict) -> str:
    env = m.get("blas_threads_env")
    if isinstance(env, dict) and env:
        return ", ".join(f"{k}={v}" for k, v in env.items())
    return "default BLAS threads"


def write_results_page(
    csv_path: str | Path,
    out: str | Path,
    *,
    figure_dir: str | Path | None = None,
    benchmarks: Sequence[str | Path] = (),
) -> Path:
    """Read the CSV (and study.json next to it), draw the figures, write the markdown page."""
    csv_path, out = Path(csv_path), Path(out)
    rows = read_csv(csv_path)
    meta_path = csv_path.with_name(META_NAME)
    meta = json.loads(meta_path.read_text()) if meta_path.exists() else None
    figure_dir = Path(figure_dir) if figure_dir else out.parent / out.stem
    paths = plot_study(rows, figure_dir)
    for source in (csv_path, meta_path):  # the page's data next to its figures
        target = figure_dir / source.name
        if source.exists() and source.resolve() != target.resolve():
            shutil.copyfile(source, target)
    rel = {k: os.path.relpath(p, out.parent) for k, p in zip(FIGURES, paths, strict=True)}
    if isinstance(benchmarks, (str, Path)):
        benchmarks = [benchmarks]
    bench = [json.loads(Path(b).read_text()) for b in benchmarks or ()]
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(results_page(rows, meta=meta, figures=rel, benchmarks=bench))
    return out


def main(quick: bool = False, out: str | Path = "convergence-out") -> int:
    """What ``fretbem convergence`` runs: the study, its CSV, figures and results.md."""
    out = Path(out)
    rows = run_study(StudyPlan.quick() if quick else StudyPlan.full(), out)
    meta = json.loads((out / META_NAME).read_text())
    (out / "results.md").write_text(results_page(rows, meta=meta))
    print(f"wrote {out / CSV_NAME}, {out / META_NAME}, figures and {out / 'results.md'}")
    return 0


__all__ = [
    "COLUMNS",
    "FAMILIES",
    "Case",
    "StudyPlan",
    "crossings",
    "exponents",
    "first_crossing",
    "fit_exponent",
    "measure",
    "plot_study",
    "read_csv",
    "results_page",
    "run_study",
    "traction_change",
    "write_csv",
    "write_results_page",
]
