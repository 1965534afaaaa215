"""A run with its accuracy: fixed pairs or an adaptive contact mesh, every step with an estimate.

:func:`solve` is the one call: ``Accuracy(mesh="fixed")`` solves the given pairs and a
companion level of about half as many (uniform) and estimates each step's discretisation
error from the two; ``Accuracy(mesh="adaptive")`` asks
:func:`fretbem.accuracy.adaptive.run_adaptive`
for a tolerance or a pair budget and keeps its estimate. The estimate is attached to the
steps (``StepResult.estimate``) and the levels to the result (``SimulationResult.accuracy``);
where no estimate can be formed the result says why instead of failing
(docs/how-to/accuracy.rst).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import attrs
import numpy as np

from fretbem.accuracy import estimate
from fretbem.accuracy.adaptive import (
    AdaptiveSettings,
    elements_for,
    pairs_for,
    remesh,
    run_adaptive,
)
from fretbem.errors import InputError
from fretbem.results import AccuracyRecord, Estimate
from fretbem.scenes.builder import build
from fretbem.simulation import run
from fretbem.validators import count_field, flag_field, number_field

__all__ = [
    "MESHES",
    "UNIFORM_RATE",
    "Accuracy",
    "AccuracyError",
    "companion_pairs",
    "estimate_blocker",
    "mode_of",
    "solve",
    "solve_scene",
]

MESHES = ("fixed", "adaptive")
#: rate of the Richardson factor for the fixed mode's two uniform levels: 1, so the factor is
#: 1 / (n / n_c - 1), about 1 for half the pairs (the change itself). The uniform error is a
#: sawtooth in the pair count (where the contact edge falls between two points), not a power
#: law; measured on the reference scene, pairs 31 to 81 (docs/how-to/accuracy.rst): the
#: estimate is 0.73 to 39.5 times the true error (max of p and q), never below 0.73.
UNIFORM_RATE = 1.0
#: fewest pairs of the fixed mode's companion level
MIN_COMPANION = 5
#: pairs of the adaptive mode's first (uniform) level, or the budget if smaller
FIRST_LEVEL = 31


class AccuracyError(InputError):
    """A mesh mode or its settings that cannot work for this run."""


def _fraction(where: str, value: float) -> None:
    if not 0.0 < value < 1.0:
        raise AccuracyError(
            f"{where}: tolerance is a fraction of p0 and f p0, 0 < tolerance < 1; got "
            f"{value!r}; give e.g. 0.02 for 2 %"
        )


@attrs.frozen
class Accuracy:
    """How a run meets its accuracy: the mesh mode and whether to estimate.

    Attributes
    ----------
    mesh : str
        ``"fixed"`` (the simulation's own pairs) or ``"adaptive"`` (re-meshed contact faces).
    estimate : bool
        Fixed mode: also solve a companion level of about half the pairs for the estimate
        (at 61 pairs about half the time of the main solve: the bodies are assembled again).
        The adaptive mode always estimates (from its own levels).
    tolerance : float
        Adaptive: stop when the estimated max error (fraction of p0 and f p0) is below it.
    budget : int
        Adaptive: most pairs of the last level.
    """

    mesh: str = attrs.field(default="fixed")
    estimate: bool = attrs.field(
        default=True, converter=flag_field("give True or False", error=AccuracyError)
    )
    tolerance: float = attrs.field(
        default=0.02,
        converter=number_field(
            "a fraction of p0", "give e.g. 0.02 for 2 %", check=_fraction, error=AccuracyError
        ),
    )
    budget: int = attrs.field(
        default=61,
        converter=count_field(
            "give the most pairs of the adaptive mode, e.g. 61",
            low=MIN_COMPANION,
            error=AccuracyError,
        ),
    )

    @mesh.validator
    def _mesh(self, attribute, value) -> None:
        if value not in MESHES:
            raise AccuracyError(f"mesh must be one of {list(MESHES)}, got {value!r}")

    def __attrs_post_init__(self) -> None:
        if self.mesh == "adaptive" and not self.estimate:
            raise AccuracyError(
                "the adaptive mode always estimates its error (its levels give it); "
                "estimate = false applies to mesh = 'fixed' only"
            )


def mode_of(scene) -> Accuracy:
    """The :class:`Accuracy` a scene's ``[contact]`` table asks for."""
    contact = scene.contact
    return Accuracy(
        mesh=contact.mesh,
        estimate=contact.estimate,
        tolerance=contact.tolerance,
        budget=contact.budget,
    )


def _contact_family(simulation):
    """(family, degree) of the upper body's contact face."""
    pair = simulation.pair
    return pair.upper.family, pair.upper.face_refinement(pair.upper_tag).degree


def companion_pairs(simulation) -> int:
    """Pairs of the fixed mode's companion level: half the contact elements, uniform."""

    family, degree = _contact_family(simulation)
    elements = elements_for(family, int(simulation.pair.n_pairs), degree)
    return pairs_for(family, max(1, elements // 2), degree)


def estimate_blocker(simulation) -> str | None:
    """Why no two-level estimate can be formed for this simulation, or None if it can."""

    pair = simulation.pair
    for body, tag in ((pair.lower, pair.lower_tag), (pair.upper, pair.upper_tag)):
        try:
            estimate.contact_segment(body, tag)
            body.face_refinement(tag)  # the companion level re-meshes the face
        except InputError as err:  # UnsupportedError and EstimateInputError among them
            return str(err)
    return None


def _uniform(simulation):
    """Companion factory of a bare simulation: its contact faces re-meshed uniformly."""

    def make(pairs: int):
        return remesh(simulation, np.array([]), pairs, ratio=1.0)

    return make


#: an estimated error above this fraction of p0 (or f p0) is reported as a caution
COARSE_ERROR = 0.10


def _largest(estimated: dict | None) -> tuple[float, str, str] | None:
    """(largest estimated max error, its key, its step) or None without an estimate."""
    if not estimated:
        return None
    return max(
        ((float(e.get(k) or 0.0), k, name) for name, e in estimated.items()
         for k in ("e_p_max", "e_q_max")),
        default=None,
    )  # fmt: skip


def _caution(accuracy: dict, estimated: dict | None) -> str | None:
    """What the user must know about the accuracy: a tolerance the adaptive mesh missed, a
    coarse fixed mesh, or no estimate at all for a mesh too coarse to have one."""
    largest = _largest(estimated)
    if accuracy.get("mesh") == "adaptive" and largest is not None:
        tolerance = accuracy.get("tolerance")
        if tolerance is not None and largest[0] > tolerance:
            return (
                f"the adaptive mesh stopped at {max(accuracy['levels'])} pairs (its budget) "
                f"with an estimated {largest[1]} of {100 * largest[0]:.3g} % at step "
                f"{largest[2]!r}, above the tolerance of {100 * tolerance:.3g} %: raise "
                "[contact] budget, or accept a larger tolerance"
            )
    elif largest is not None and largest[0] > COARSE_ERROR:
        return (
            f"the estimated {largest[1]} is {100 * largest[0]:.3g} % at step {largest[2]!r}: "
            "the contact mesh is coarse; raise [contact] pairs (or use mesh = 'adaptive' "
            "with a tolerance)"
        )
    elif largest is None and "too few" in str(accuracy.get("estimate_reason") or ""):
        return (
            f"{max(accuracy['levels'])} pairs (too coarse) give no estimate, so the error is "
            f"unknown (and likely large); use at least {2 * MIN_COMPANION + 1} pairs"
        )
    return None


def _attach(result, estimated: dict | None, accuracy: dict):
    """The result with each step's estimate and the run's accuracy record."""
    caution = _caution(accuracy, estimated)
    if caution is not None:
        accuracy = {
            **accuracy,
            "caution": (accuracy["caution"] + "; " if accuracy.get("caution") else "") + caution,
        }
    steps = result.steps
    if estimated is not None:
        steps = tuple(attrs.evolve(s, estimate=Estimate.of(estimated[s.name])) for s in steps)
    return attrs.evolve(result, steps=steps, accuracy=AccuracyRecord(**accuracy))


def _fixed(simulation, mode: Accuracy, coarse, run_kwargs) -> object:
    start = time.perf_counter()
    result = run(simulation, **run_kwargs)
    pairs = int(result.steps[0].x.size)
    record = {"mesh": "fixed", "levels": [pairs], "estimate_reason": None}

    def done(reason=None, estimated=None, levels=(pairs,)):
        record.update(levels=list(levels), seconds=time.perf_counter() - start)
        record["estimate_reason"] = reason
        return _attach(result, estimated, record)

    if not mode.estimate:
        return done("not asked (estimate = false)")
    reason = estimate_blocker(simulation)
    if reason is not None:
        return done(reason)
    try:
        n_coarse = companion_pairs(simulation)
    except (ValueError, AttributeError) as err:
        return done(f"no companion level: {err}")
    if n_coarse < MIN_COMPANION or n_coarse >= pairs:
        return done(
            f"{pairs} pairs are too few for a companion level of about half as many "
            f"(at least {MIN_COMPANION}); use more pairs"
        )
    try:
        lower = run(coarse(n_coarse), check=run_kwargs.get("check", True))
        estimated = estimate.estimate_errors(lower, result, rate=UNIFORM_RATE)
    except Exception as err:  # the estimate never fails a run that succeeded
        text = " ".join(str(err).split())
        return done(f"the companion level of {n_coarse} pairs failed: {text}")
    record.update(
        rate=UNIFORM_RATE,
        factor=estimate.richardson_factor(n_coarse, pairs, UNIFORM_RATE),
    )
    return done(None, estimated, (n_coarse, pairs))


#: most pairs of an adaptive level the mode solves, the finest verified (graded faces of 481
#: to 521 points converge, both families and body models; docs/explanation/adaptive.rst,
#: "Limits"); larger budgets stop here and say so
MAX_ADAPTIVE_PAIRS = 521


def adaptive_blocker(simulation) -> str | None:
    """Why the adaptive mode cannot re-mesh this simulation, or None if it can."""
    reason = estimate_blocker(simulation)
    if reason is None:
        return None
    return f"mesh = 'adaptive' cannot re-mesh this scene ({reason}); use mesh = 'fixed'"


def _adaptive(simulation, mode: Accuracy, bars=None) -> object:
    reason = adaptive_blocker(simulation)
    if reason is not None:
        raise AccuracyError(reason)
    budget = min(mode.budget, MAX_ADAPTIVE_PAIRS)
    settings = AdaptiveSettings(
        tolerance=mode.tolerance, budget=budget, first=min(FIRST_LEVEL, budget)
    )
    out = run_adaptive(simulation, settings, progress=bars)
    summary = out.summary()
    record = {
        "mesh": "adaptive",
        "levels": summary["levels"],
        "seconds": summary["seconds"],
        "tolerance": mode.tolerance,
        "budget": mode.budget,
        "transitions": summary["transitions"],
        "estimate_reason": None,
    }
    notes = list(out.notes)
    if budget < mode.budget:
        notes.append(
            f"budget {mode.budget} capped at {MAX_ADAPTIVE_PAIRS} pairs: finer graded contact "
            "faces are not verified (docs/explanation/adaptive.rst, 'Limits')"
        )
    if notes:
        record["caution"] = "; ".join(notes)
    return _attach(out.result, out.estimate, record)


def solve(
    simulation,
    mode: Accuracy | None = None,
    *,
    coarse: Callable[[int], object] | None = None,
    progress=None,
    check: bool = True,
    bars=None,
    memo=None,
):
    """Solve ``simulation`` in ``mode`` (default: fixed pairs with an estimate).

    Returns the :class:`~fretbem.results.SimulationResult` of the finest level; each step's
    ``estimate`` holds the estimated error (keys of ``StepResult.errors``) or None, and
    ``result.accuracy`` the mode, the levels' pairs, their time and ``estimate_reason``
    (why there is no estimate, else None). ``coarse(pairs)`` builds the fixed mode's
    companion level (default: the contact faces re-meshed uniformly). ``progress(k, n, step)``
    follows the steps of the (fixed) level; ``bars(description, total)`` makes a progress bar
    (the adaptive levels). ``memo`` (a :class:`~fretbem.solvers.step_memo.StepMemo`) lends
    the fixed level the load steps earlier runs on the same problem solved.
    """
    mode = mode or Accuracy()
    if mode.mesh == "adaptive":
        return _adaptive(simulation, mode, bars)
    kwargs = {"check": check}
    if progress is not None:
        kwargs["progress"] = progress
    if memo is not None:
        kwargs["memo"] = memo
    return _fixed(simulation, mode, coarse or _uniform(simulation), kwargs)


def solve_scene(scene, mode: Accuracy | None = None, *, progress=None):
    """Build and solve a :class:`~fretbem.scenes.spec.Scene` in its own mode (or ``mode``).

    The fixed mode's companion level is the same scene with fewer ``pairs``. Returns
    (result, reason): ``reason`` says why no closed form applies (None if one does).
    """

    simulation, reason = build(scene)
    result = solve(
        simulation,
        mode or mode_of(scene),
        coarse=lambda pairs: build(scene, pairs=pairs)[0],
        progress=progress,
    )
    return result, reason
