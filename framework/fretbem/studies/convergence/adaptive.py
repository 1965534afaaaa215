"""The adaptive mode in the convergence study: a series per pair budget, and the sawtooth.

*Budget series*: :func:`fretbem.accuracy.adaptive.run_adaptive` on the reference scene at a few pair
budgets per family, with the same error keys as the fixed-pairs runs (largest over steps
B-E) and the adaptive estimate beside them. DOFs are those of the finest level; times are
of all levels (building the scene, every assembly, condensation and solve).

*Sawtooth*: at every pair count N of a range, the fixed mode with ``pairs = N`` and the
adaptive mode with budget N, once each: the fixed mode's largest error jumps with where the
pairs fall relative to the contact edges and stick-slip boundaries, the adaptive one should
not (docs/explanation/adaptive.rst).

The study asks for a tolerance small enough that the budget, not the estimate, ends every
run, so each budget is a discretisation of its own.
"""

from __future__ import annotations

import gc
import statistics
import time
from collections.abc import Callable, Iterator, Sequence

import attrs

from fretbem import registry as bases
from fretbem.accuracy import adaptive
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import run

from .io import ERROR_STEPS, ERRORS

#: (family, degree) of the adaptive series; degree None is the family's default
ADAPTIVE_FAMILIES = (("nurbs", 2), ("lagrange2", None))
FULL_BUDGETS = (31, 41, 61, 81, 121)
QUICK_BUDGETS = (31, 41)
#: first and last pair count of the sawtooth
FULL_SAWTOOTH = (31, 121)
QUICK_SAWTOOTH = (31, 33)
#: tolerance of the study's adaptive runs: below any estimate, so the budget ends the run
TOLERANCE = 1e-6
ADAPTIVE_NAME, SAWTOOTH_NAME = "adaptive_study.csv", "adaptive_study_sawtooth.csv"

ADAPTIVE_COLUMNS = (
    "family",
    "degree",
    "budget",
    "pairs",
    "levels",
    "dofs",
    *ERRORS,
    *(f"estimate_{e}" for e in ERRORS),
    "iterations",
    "adaptive_s",
    "wall_s",
    "repeats",
    "tolerance",
)
SAWTOOTH_COLUMNS = (
    "family",
    "degree",
    "pairs",
    "fixed_dofs",
    *(f"fixed_{e}" for e in ERRORS),
    "fixed_wall_s",
    "adaptive_pairs",
    "adaptive_dofs",
    *(f"adaptive_{e}" for e in ERRORS),
    *(f"estimate_{e}" for e in ERRORS),
    "adaptive_wall_s",
)


@attrs.frozen
class AdaptiveCase:
    """One adaptive run of the study: a family on the reference scene with a pair budget."""

    family: str
    degree: int | None
    budget: int

    def scene(self) -> CattaneoMindlinScene:
        return attrs.evolve(
            CattaneoMindlinScene(), basis=self.family, degree=self.degree, pairs=self.budget
        )

    def settings(self, tolerance: float = TOLERANCE) -> adaptive.AdaptiveSettings:
        return adaptive.AdaptiveSettings(budget=self.budget, tolerance=tolerance)

    def label(self) -> str:
        degree = "" if self.degree is None else f" p={self.degree}"
        return f"{self.family}{degree} adaptive, budget {self.budget}"


def worst(steps_errors: dict[str, dict]) -> dict[str, float]:
    """Largest of each error key over steps B-E of a {step name: errors} mapping."""
    return {e: max(steps_errors[s][e] for s in ERROR_STEPS) for e in ERRORS}


def _errors(result) -> dict[str, float]:
    return worst({s.name: s.errors for s in result.steps})


def _timed_adaptive(case: AdaptiveCase, tolerance: float):
    """(AdaptiveResult, wall s from building the scene to the last level)."""
    gc.collect()
    tic = time.perf_counter()
    out = adaptive.run_adaptive(cattaneo_mindlin(case.scene()), case.settings(tolerance))
    return out, time.perf_counter() - tic


def measure_adaptive(case: AdaptiveCase, repeats: int = 1, tolerance: float = TOLERANCE) -> dict:
    """One row of the budget series; times are medians over ``repeats`` runs."""
    runs = [_timed_adaptive(case, tolerance) for _ in range(max(1, repeats))]
    out = runs[0][0]
    info = out.result.describe()
    return {
        "family": case.family,
        "degree": info["degree"],
        "budget": case.budget,
        "pairs": info["pairs"],
        "levels": "/".join(str(level.describe()["pairs"]) for level in out.levels),
        "dofs": info["dofs"],
        **_errors(out.result),
        **{f"estimate_{e}": v for e, v in worst(out.estimate).items()},
        "iterations": sum(s.iterations for level in out.levels for s in level.steps),
        "adaptive_s": float(statistics.median(o.seconds for o, _ in runs)),
        "wall_s": float(statistics.median(w for _, w in runs)),
        "repeats": len(runs),
        "tolerance": tolerance,
    }


def placeable(family: str, degree: int | None, pairs: int) -> bool:
    """Whether the family puts exactly ``pairs`` collocation points on the contact zone."""
    plugin = bases.get(family)
    return adaptive.pairs_for(plugin, adaptive.elements_for(plugin, pairs, degree), degree) == pairs


def sawtooth(
    families: Sequence[tuple[str, int | None]],
    span: tuple[int, int],
    tolerance: float = TOLERANCE,
) -> Iterator[dict]:
    """Rows of the sawtooth: per family, every placeable pair count of ``span``, one fixed
    and one adaptive run each (single timings: the figure is about errors)."""
    first, last = span
    for family, degree in families:
        for n in range(first, last + 1):
            if not placeable(family, degree, n):
                continue
            case = AdaptiveCase(family, degree, n)
            gc.collect()
            tic = time.perf_counter()
            fixed = run(cattaneo_mindlin(case.scene()))
            fixed_wall = time.perf_counter() - tic
            out, wall = _timed_adaptive(case, tolerance)
            info, fixed_info = out.result.describe(), fixed.describe()
            yield {
                "family": family,
                "degree": fixed_info["degree"],
                "pairs": fixed_info["pairs"],
                "fixed_dofs": fixed_info["dofs"],
                **{f"fixed_{e}": v for e, v in _errors(fixed).items()},
                "fixed_wall_s": fixed_wall,
                "adaptive_pairs": info["pairs"],
                "adaptive_dofs": info["dofs"],
                **{f"adaptive_{e}": v for e, v in _errors(out.result).items()},
                **{f"estimate_{e}": v for e, v in worst(out.estimate).items()},
                "adaptive_wall_s": wall,
            }


def run_adaptive_series(
    cases: Sequence[AdaptiveCase],
    repeats: int,
    tolerance: float,
    write: Callable[[list[dict]], None],
    say: Callable[[str], None],
) -> list[dict]:
    """Measure every case; ``write`` gets all rows so far after each run."""
    rows: list[dict] = []
    for k, case in enumerate(cases, 1):
        rows.append(measure_adaptive(case, repeats, tolerance))
        write(rows)
        r = rows[-1]
        say(
            f"[{k:3d}/{len(cases)}] {case.label():<38} {r['dofs']:5d} DOFs  "
            f"e_q max {100 * r['e_q_max']:6.3f} % (est {100 * r['estimate_e_q_max']:6.3f})  "
            f"L2 {100 * r['e_q_l2']:6.3f} %  wall {r['wall_s']:6.2f} s  levels {r['levels']}"
        )
    return rows


__all__ = [
    "ADAPTIVE_COLUMNS",
    "ADAPTIVE_FAMILIES",
    "SAWTOOTH_COLUMNS",
    "AdaptiveCase",
    "measure_adaptive",
    "placeable",
    "run_adaptive_series",
    "sawtooth",
    "worst",
]
