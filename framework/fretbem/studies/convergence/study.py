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

The adaptive mode runs beside the fixed pairs: a series of pair budgets per family and the
sawtooth of both modes at every pair count of a range (:mod:`.convergence_adaptive`).

``run_study`` writes ``convergence.csv`` (one row per run, rewritten after every run),
``adaptive_study.csv``, ``adaptive_study_sawtooth.csv``, ``study.json`` (machine and plan)
and three figures; the documentation's results page is generated from them by
``benchmarks/results_page.py``. The paper's and CalculiX's
numbers the figures compare with are data, with their sources, in ``references.toml``.
Timings are medians over ``repeats`` runs; the peak memory
is the ``tracemalloc`` peak of one separate run (Python and numpy allocations from building
the scene to the last step, not the interpreter's resident size).
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

import attrs

from fretbem import registry as bases
from fretbem.errors import InputError
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.validators import (
    count_field,
    flag_field,
    positive_field,
    real_number,
    shown,
    whole_number,
)

from .adaptive import (
    ADAPTIVE_COLUMNS,
    ADAPTIVE_FAMILIES,
    ADAPTIVE_NAME,
    FULL_BUDGETS,
    FULL_SAWTOOTH,
    QUICK_BUDGETS,
    QUICK_SAWTOOTH,
    SAWTOOTH_COLUMNS,
    SAWTOOTH_NAME,
    TOLERANCE,
    AdaptiveCase,
    run_adaptive_series,
    sawtooth,
)
from .analysis import (  # noqa: F401 - re-exported for the study's users
    CALCULIX,
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
    series,
)
from .figures import plot_sawtooth, plot_study
from .io import (  # noqa: F401 - re-exported for the study's users
    COLUMNS,
    ERROR_STEPS,
    ERRORS,
    STEPS,
    machine,
    read_csv,
    write_csv,
)
from .runs import Case, measure, traction_change, tractions

#: (family, degree) of the study; degree None is the family's default
FAMILIES = (("nurbs", 2), ("nurbs", 3), ("nurbs", 4), ("lagrange2", None))
FULL_PAIRS = (15, 31, 61, 121, 241, 481)
QUICK_PAIRS = (15, 31)
CSV_NAME, META_NAME = "convergence.csv", "study.json"


def _sequence(where: str, value: Any, what: str, fix: str) -> list:
    """A plan's list or tuple (or numpy array) as a list; text, a mapping or a number is
    refused (``pairs=61`` or ``pairs="61"`` is not a tuple of pair counts)."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise InputError(f"{where} must be a tuple of {what}, got {shown(value)}; {fix}")
    return list(value)


def _counts_field() -> attrs.Converter:
    """A tuple of pair counts: whole numbers >= 1 (each family's rule is checked after)."""
    fix = "give a tuple of pair counts, e.g. (15, 31, 61)"

    def convert(value: Any, instance: Any, field: Any) -> tuple[int, ...]:
        where = f"StudyPlan.{field.name}"
        items = _sequence(where, value, "pair counts", fix)
        return tuple(whole_number(f"{where}[{k}]", v, low=1, fix=fix) for k, v in enumerate(items))

    return attrs.Converter(convert, takes_self=True, takes_field=True)


def _factors_field() -> attrs.Converter:
    """A tuple of factors > 0 on the element counts of the rest of the boundary."""
    fix = "give a tuple of factors > 0, e.g. (0.5, 2.0)"

    def convert(value: Any, instance: Any, field: Any) -> tuple[float, ...]:
        where = f"StudyPlan.{field.name}"
        out = []
        for k, v in enumerate(_sequence(where, value, "factors", fix)):
            number = real_number(f"{where}[{k}]", v, what="a factor on element counts",
                                 fix=fix, error=InputError)  # fmt: skip
            if number <= 0:
                raise InputError(f"{where}[{k}] must be > 0, got {shown(v)}; {fix}")
            out.append(number)
        return tuple(out)

    return attrs.Converter(convert, takes_self=True, takes_field=True)


_DEGREE_FIX = "give a whole degree >= 1, or None for the family's default"


def _families_field(none: bool = False) -> attrs.Converter:
    """A tuple of (family, degree): an installed basis family's name and a whole degree
    >= 1, or None for its default (``none``: None for the whole field too)."""
    fix = 'give a tuple of (family, degree) pairs, e.g. (("nurbs", 2), ("lagrange2", None))'

    def convert(value: Any, instance: Any, field: Any):
        where = f"StudyPlan.{field.name}"
        if value is None and none:
            return None
        out = []
        for k, entry in enumerate(_sequence(where, value, "(family, degree) pairs", fix)):
            here = f"{where}[{k}]"
            pair = not isinstance(entry, (str, bytes)) and isinstance(entry, Iterable)
            entry = list(entry) if pair else entry
            if not pair or len(entry) != 2 or not isinstance(entry[0], str):
                raise InputError(f"{here} must be a (family name, degree) pair, got "
                                 f"{shown(entry)}; {fix}")  # fmt: skip
            name, degree = entry
            if name not in bases.available():
                raise InputError(
                    f"{here}: unknown basis family {name!r}; give one of the installed "
                    f"families: {', '.join(map(repr, bases.available()))}"
                )
            if degree is not None:
                degree = whole_number(f"{here} degree", degree, low=1, fix=_DEGREE_FIX)
            out.append((name, degree))
        return tuple(out)

    return attrs.Converter(convert, takes_self=True, takes_field=True)


def _span_field(value: Any) -> tuple[int, ...]:
    """The sawtooth's (first, last) pair counts, first <= last, or () for none."""
    fix = "give (first, last) pair counts, e.g. (31, 121), or () for no sawtooth"
    items = _sequence("StudyPlan.sawtooth", value, "two pair counts", fix)
    if not items:
        return ()
    if len(items) != 2:
        raise InputError(f"StudyPlan.sawtooth must be (first, last), got {shown(value)}; {fix}")
    first, last = (whole_number(f"StudyPlan.sawtooth[{k}]", v, low=1, fix=fix)
                   for k, v in enumerate(items))  # fmt: skip
    if first > last:
        raise InputError(f"StudyPlan.sawtooth must have first <= last, got {value!r}; {fix}")
    return (first, last)


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
    adaptive_families : tuple of (family, degree)
        Families of the adaptive series and the sawtooth.
    budgets : tuple of int
        Pair budgets of the adaptive series (timed like the cases, ``repeats`` runs).
    sawtooth : tuple of (first, last) pair count, or ()
        Range of the sawtooth, every pair count the family can place (single runs).
    tolerance : float
        Tolerance of the adaptive runs (the default is below any estimate: the budget ends
        every run).
    """

    families: tuple[tuple[str, int | None], ...] = attrs.field(
        default=FAMILIES, converter=_families_field()
    )
    pairs: tuple[int, ...] = attrs.field(default=FULL_PAIRS, converter=_counts_field())
    large_pairs: tuple[int, ...] = attrs.field(default=FULL_PAIRS, converter=_counts_field())
    rest_pairs: tuple[int, ...] = attrs.field(default=(61, 481), converter=_counts_field())
    rest_factors: tuple[float, ...] = attrs.field(
        default=(0.5, 2.0, 4.0), converter=_factors_field()
    )
    check_families: tuple[tuple[str, int | None], ...] | None = attrs.field(
        default=None, converter=_families_field(none=True)
    )
    repeats: int = attrs.field(default=3, converter=count_field("give e.g. 3 (the default)"))
    memory: bool = attrs.field(default=True, converter=flag_field("give True or False"))
    adaptive_families: tuple[tuple[str, int | None], ...] = attrs.field(
        default=ADAPTIVE_FAMILIES, converter=_families_field()
    )
    budgets: tuple[int, ...] = attrs.field(default=FULL_BUDGETS, converter=_counts_field())
    sawtooth: tuple[int, ...] = attrs.field(default=FULL_SAWTOOTH, converter=_span_field)
    tolerance: float = attrs.field(
        default=TOLERANCE,
        converter=positive_field("the adaptive runs' tolerance", f"give e.g. {TOLERANCE:g}"),
    )

    def __attrs_post_init__(self) -> None:
        """Every run is built as a scene record now, so a pair count a family cannot place
        or a degree it does not have is refused before the first of hours of runs."""
        for case in [*self.cases(), *self.adaptive_cases()]:
            try:
                case.scene().zone_elements(bases.get(case.family))
                if isinstance(case, AdaptiveCase):
                    case.settings(self.tolerance)
            except (InputError, ValueError) as err:
                raise InputError(
                    f"StudyPlan: the run {case.label()!r} cannot be built: {err}"
                ) from None

    @classmethod
    def full(cls) -> StudyPlan:
        return cls()

    @classmethod
    def quick(cls) -> StudyPlan:
        """A few small levels for CI: every family at 15 and 31 pairs; checks at 31 pairs
        for nurbs p=2 and lagrange2; their adaptive budgets 31 and 41, sawtooth 31 to 33."""
        return cls(
            pairs=QUICK_PAIRS,
            large_pairs=QUICK_PAIRS[-1:],
            rest_pairs=QUICK_PAIRS[-1:],
            rest_factors=(2.0,),
            check_families=(("nurbs", 2), ("lagrange2", None)),
            repeats=1,
            budgets=QUICK_BUDGETS,
            sawtooth=QUICK_SAWTOOTH,
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

    def adaptive_cases(self) -> list[AdaptiveCase]:
        """The adaptive series: every adaptive family at every budget."""
        return [AdaptiveCase(f, d, b) for f, d in self.adaptive_families for b in self.budgets]


# -- the study ----------------------------------------------------------------------------
def run_study(
    plan: StudyPlan | None = None,
    out: str | Path = "convergence-out",
    *,
    figures: bool = True,
    progress: Callable[[str], None] | None = print,
) -> list[dict]:
    """Run every case of ``plan``, then the adaptive series and the sawtooth; the CSVs are
    written after each run, then study.json and the figures. Returns the fixed-pairs rows."""
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
    adaptive_rows = run_adaptive_series(
        plan.adaptive_cases(),
        plan.repeats,
        plan.tolerance,
        lambda done: write_csv(done, out / ADAPTIVE_NAME, ADAPTIVE_COLUMNS),
        say,
    )
    tooth_rows = _run_sawtooth(plan, out / SAWTOOTH_NAME, say)
    meta["seconds"] = time.perf_counter() - start
    meta["machine_after"] = {"load_average_1min": machine()["load_average_1min"]}
    (out / META_NAME).write_text(json.dumps(meta, indent=2))
    if figures:
        paths = plot_study(rows, out, adaptive_rows)
        paths += plot_sawtooth(tooth_rows, out)
        say(f"wrote {', '.join(str(p) for p in paths)}")
    say(f"study done in {meta['seconds']:.1f} s")
    return rows


def _run_sawtooth(plan: StudyPlan, path: Path, say: Callable[[str], None]) -> list[dict]:
    """The sawtooth of ``plan`` (nothing if its range is empty), written after every row."""
    rows: list[dict] = []
    if not plan.sawtooth:
        return rows
    span = (plan.sawtooth[0], plan.sawtooth[-1])
    say(f"sawtooth: pairs {span[0]} to {span[1]}, fixed and adaptive; writing {path}")
    for row in sawtooth(plan.adaptive_families, span, plan.tolerance):
        rows.append(row)
        write_csv(rows, path, SAWTOOTH_COLUMNS)
        say(
            f"  {row['family']:<10} {row['pairs']:4d} pairs  e_q max fixed "
            f"{100 * row['fixed_e_q_max']:6.3f} %  adaptive {100 * row['adaptive_e_q_max']:6.3f} %"
        )
    return rows


# -- command line ---------------------------------------------------------------------------
def run_command(args) -> int:
    """Run a parsed ``fretbem convergence`` command line (``--quick``, ``--out``)."""
    return main(quick=args.quick, out=args.out)


def main(quick: bool = False, out: str | Path = "convergence-out") -> int:
    """What ``fretbem convergence`` runs: the study, its CSVs, study.json and the figures.

    Prints where the 1 % shear error is first reached per family (in DOFs and seconds) and
    the adaptive series per budget.
    """
    out = Path(out)
    rows = run_study(StudyPlan.quick() if quick else StudyPlan.full(), out)
    names = (CSV_NAME, ADAPTIVE_NAME, SAWTOOTH_NAME, META_NAME)
    print(f"wrote {', '.join(str(out / name) for name in names)} and figures")
    for key, (dofs, seconds) in crossings(rows, "e_q_max").items():
        where = "not reached" if dofs is None else f"{dofs:.0f} DOFs, {seconds:.3g} s"
        print(f"  {family_label(key)}: e_q max {100 * TARGET:g} % at {where}")
    adaptive = out / ADAPTIVE_NAME
    for r in read_csv(adaptive) if adaptive.exists() else ():
        print(
            f"  {family_label((r['family'], r['degree']))} adaptive, budget {r['budget']}: "
            f"{r['dofs']} DOFs, {r['wall_s']:.3g} s, e_q max {100 * r['e_q_max']:.3f} % "
            f"(estimate {100 * r['estimate_e_q_max']:.3f} %)"
        )
    return 0


__all__ = [
    "COLUMNS",
    "FAMILIES",
    "AdaptiveCase",
    "Case",
    "StudyPlan",
    "measure",
    "read_csv",
    "run_study",
    "traction_change",
    "write_csv",
]
