"""Speed against error: the convergence study of the reference Cattaneo-Mindlin scene.

Every basis family and degree of the study is run on the reference scene
(docs/theory.md) at increasing numbers of node pairs in the candidate contact
zone. Each run records the errors of steps B-E against Mindlin-Deresiewicz theory, the
Newton iterations, the times of assembly, condensation and every step, the wall time and the
peak memory. Two checks go with it:

- *finite bodies*: the scene's bodies are finite (w ~ 20 a) while the theory is for half
  planes, so the same discretisations are also run on bodies four times larger; the
  difference between the two is the finite-body effect, not discretisation error;
- *refinement of the rest*: the flanks, sides and top/bottom are re-run with their element
  counts scaled, and the largest change of the contact tractions is reported.

``run_study`` writes ``convergence.csv`` (one row per run, rewritten after every run),
``study.json`` (machine and plan) and two log-log figures; the documentation's results page
is generated from the CSV by ``benchmarks/results_page.py``. The paper's and CalculiX's
numbers the figures compare with are data, with their sources, in ``references.toml``.
Timings are medians over ``repeats`` runs; the peak memory
is the ``tracemalloc`` peak of one separate run (Python and numpy allocations from building
the scene to the last step, not the interpreter's resident size).
"""

from __future__ import annotations

import csv
import gc
import json
import math
import os
import platform
import statistics
import time
import tracemalloc
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import attrs
import numpy as np

from ..scenes import CattaneoMindlinScene, cattaneo_mindlin
from ..simulation import run
from .convergence_analysis import (  # noqa: F401 - re-exported for the study's users
    CALCULIX,
    ERRORS,
    FIGURES,
    LARGE,
    PAPER_E_Q,
    PAPER_PAIRS,
    REFERENCES,
    TARGET,
    crossings,
    exponents,
    family_label,
    first_crossing,
    fit_exponent,
    main_rows,
    plot_study,
    series,
)

STEPS = ("A", "B", "C", "D", "E")
#: steps whose errors are reported (A has no shear)
ERROR_STEPS = ("B", "C", "D", "E")
#: (family, degree) of the study; degree None is the family's default
FAMILIES = (("nurbs", 2), ("nurbs", 3), ("nurbs", 4), ("lagrange2", None))
FULL_PAIRS = (15, 31, 61, 121, 241, 481)
QUICK_PAIRS = (15, 31)
CSV_NAME, META_NAME = "convergence.csv", "study.json"

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


# -- command line ---------------------------------------------------------------------------
def main(quick: bool = False, out: str | Path = "convergence-out") -> int:
    """What ``fretbem convergence`` runs: the study, its CSV, study.json and the figures.

    Prints where the 1 % shear error is first reached per family (in DOFs and seconds).
    """
    out = Path(out)
    rows = run_study(StudyPlan.quick() if quick else StudyPlan.full(), out)
    print(f"wrote {out / CSV_NAME}, {out / META_NAME} and figures")
    for key, (dofs, seconds) in crossings(rows, "e_q_max").items():
        where = "not reached" if dofs is None else f"{dofs:.0f} DOFs, {seconds:.3g} s"
        print(f"  {family_label(key)}: e_q max {100 * TARGET:g} % at {where}")
    return 0


__all__ = [
    "COLUMNS",
    "FAMILIES",
    "Case",
    "StudyPlan",
    "measure",
    "read_csv",
    "run_study",
    "traction_change",
    "write_csv",
]
