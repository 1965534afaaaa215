"""A finite-sliding run as an ordinary :class:`~fretbem.results.SimulationResult`.

The writers, the figures and the fretting analysis read a ``SimulationResult``; a sliding
run gives one whose steps each carry the pairing they were solved with (``StepResult.pair``)
and whose ``delta`` and slips count from where the pad started. No closed form and no
companion level apply to a sliding history, so the accuracy record says why there is no
estimate.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from fretbem.results import AccuracyRecord, SimulationResult
from fretbem.simulation import Simulation

from .slide import run_sliding
from .track import Track

__all__ = ["NO_ESTIMATE", "solve_sliding", "step_solutions"]

#: why a sliding run has no error estimate (summary.json's accuracy.estimate_reason)
NO_ESTIMATE = (
    "finite sliding: the pairs move along the track, so no companion level of half the "
    "pairs is solved on the same pairing"
)


def solve_sliding(
    simulation: Simulation,
    *,
    every: float = 1.0,
    check: bool = True,
    say: Callable[[str], None] = print,
    progress: Callable | None = None,
    frame: str = "local",
) -> SimulationResult:
    """Run ``simulation`` with finite sliding (:func:`~fretbem.sliding.slide.run_sliding`,
    ``frame`` its pair frame along an arc); ``say`` receives the new-contact notes and a
    closing line on the re-pairings."""
    tic = time.perf_counter()
    sliding = run_sliding(
        simulation, every=every, check=check, note=say, progress=progress, frame=frame
    )
    seconds = time.perf_counter() - tic
    say(
        f"finite sliding: {sliding.repairings} re-pairing(s); the pad's block from "
        f"{min(sliding.positions):.4g} to {max(sliding.positions):.4g} mm along the track"
    )
    pairs = int(sliding.steps[0].x.size) if sliding.steps else 0
    record = AccuracyRecord(
        mesh="fixed", levels=(pairs,), seconds=seconds, estimate_reason=NO_ESTIMATE
    )
    pair = simulation.pair
    timings = {
        "assembly": sum(b.timings.get("assembly", 0.0) for b in (pair.upper, pair.lower)),
        "factorisation": sum(b.timings.get("factorisation", 0.0) for b in (pair.upper, pair.lower)),
        "condensation": 0.0,  # once per pairing, inside the steps' time
        "steps": sum(s.seconds for s in sliding.steps),
        "total": seconds,
    }
    return SimulationResult(
        simulation=sliding.simulation,
        steps=sliding.steps,
        timings=timings,
        accuracy=record,
    )


def step_solutions(result: SimulationResult, step) -> dict:
    """Each body's boundary solution ("upper", "lower") at ``step``: on the simulation's
    pair, or for a step of a sliding run on its own pairing with the pad's slide added to
    its block's displacement (the specimen's fields stay where they are; the pad's carry
    it along the track). On an arc the pad's fields are in its own axes, as drawn: the
    slide along the arc is added along its own tangent, its turn (s / R) is not."""
    if getattr(step, "pair", None) is None:
        return result.simulation.prepare().solutions(step.unknowns, step.loads)
    problem = step.pair.condensed()
    if result.simulation.rotates:  # about the pivot pinned where the pad started
        problem = result.simulation.rotating(problem)
    x = np.array(step.unknowns, dtype=float)
    slide = np.asarray(getattr(step.pair, "offset", 0.0))
    turn = getattr(step.pair, "turn", 0.0)
    if turn:  # the arc's slide s = turn / rate, along the pad's own tangent
        track = Track.of(result.simulation.pair)
        slide = track.slide_of(step.pair) * problem.pairing.load_frame("upper")[1]
    x[problem.layout.block("upper")] += slide
    return problem.solutions(x, step.loads)
