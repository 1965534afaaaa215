"""The contact, its stresses and its fatigue life at chosen N: life before and after wear.

At each assessed N the scene's whole load history is solved again on the worn contact
(:meth:`~fretbem.wear.run.WearResult.at`), checked like any run, and the fatigue request
evaluated on it, so the lives at N = 0 and after wear compare like for like.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs

from fretbem.fatigue import run_fatigue
from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.verification.checks import check_steps

from .run import WearResult

__all__ = ["WearAssessment", "WearReport", "assess", "format_wear"]


@attrs.frozen(eq=False)
class WearAssessment:
    """The scene's load history solved at N cycles of wear, and its fatigue assessment.

    Attributes
    ----------
    cycles : int
    result : SimulationResult
        The history on the worn contact (for stresses, figures and fatigue).
    fatigue : FatigueReport or None
    """

    cycles: int
    result: object
    fatigue: object = None


@attrs.frozen(eq=False)
class WearReport:
    """A wear history and its assessments at the requested N."""

    result: WearResult
    assessments: tuple[WearAssessment, ...] = ()


def assess(result: WearResult, cycles: Sequence[int], fatigue=None) -> WearReport:
    """Solve the history at each N of ``cycles`` on the worn contact (each step checked) and
    run the fatigue request ``fatigue`` (a FatigueRequest, or None) on it."""
    out = []
    for n in cycles:
        worn = result.at(n)
        check_steps(worn)
        report = None
        if fatigue is not None:
            report = run_fatigue(SimulationStressHistory(worn), fatigue)
        out.append(WearAssessment(n, worn, report))
    return WearReport(result, tuple(out))


def format_wear(report: WearReport) -> str:
    """Plain-text table for a terminal: depth, scar, volume and peak pressure per output N,
    then the lives at each assessed N."""
    result = report.result
    lines = [
        f"wear: {result.wear.cycles} cycles, {result.simulated} simulated, "
        f"{len(result.jumps)} jumps, {result.seconds:.2f} s",
        f"{'N':>9} {'depth pad':>10} {'specimen':>10} {'scar pad':>9} {'specimen':>9} "
        f"{'vol pad':>10} {'specimen':>10} {'peak p':>8}",
        f"{'':>9} {'(um)':>10} {'(um)':>10} {'(mm)':>9} {'(mm)':>9} {'(mm3/mm)':>10} "
        f"{'(mm3/mm)':>10} {'(MPa)':>8}",
    ]
    for snap in result.snapshots:
        prof = snap.profile
        lines.append(
            f"{snap.cycles:>9d} {1e3 * prof.max_depth('upper'):>10.4g} "
            f"{1e3 * prof.max_depth('lower'):>10.4g} {prof.scar_width('upper'):>9.4g} "
            f"{prof.scar_width('lower'):>9.4g} {prof.volume('upper'):>10.3e} "
            f"{prof.volume('lower'):>10.3e} {snap.pressure.max():>8.4g}"
        )
    for item in report.assessments:
        if item.fatigue is None:
            continue
        for method, rep in item.fatigue.methods.items():
            life = rep.life_hot_spot
            text = "none" if life is None else ("run-out" if life.runout else f"{life.cycles:.3g}")
            lines.append(f"life after N = {item.cycles} wear cycles, {method}: {text} cycles")
    return "\n".join(lines)
