"""The public run pipeline: a scene (or a simulation) solved, checked and post-processed.

``run_scene`` is what ``fretbem run`` does before it writes: build the simulation, solve it
in the scene's accuracy mode (fixed with an estimate, or adaptive), check every step, solve
the comparison families, and carry out the ``[stress]``, ``[fatigue]`` and ``[wear]``
requests. The returned :class:`RunResult` writes itself through the writers of
:func:`fretbem.output.write.write_results`. Nothing here prints; ``say`` receives the
progress lines.
"""

from __future__ import annotations

import html
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import attrs

from fretbem.accuracy import modes as accuracy
from fretbem.errors import InputError
from fretbem.output.write import analyses, write_results
from fretbem.scenes.builder import build
from fretbem.simulation import BlockTippingError, run, run_resources
from fretbem.sliding import solve_sliding
from fretbem.solvers.fallback import with_fallback
from fretbem.solvers.newton import SolverConvergenceError
from fretbem.verification.checks import check_steps

__all__ = ["RunResult", "run_scene", "run_simulation"]


def _quiet(message: str) -> None:
    """Progress lines go nowhere unless a caller asks for them."""


@attrs.frozen(eq=False)
class RunResult:
    """One run: the solved result and what was computed beside it.

    Attributes
    ----------
    result : SimulationResult
        The finest level, with its accuracy record and each step's estimate.
    reason : str or None
        Why no closed form applies (None when one does).
    stress : StressRequest or None
        The ``[stress]`` request (evaluated when written).
    fatigue : FatigueReport or None
        The fatigue assessment of the ``[fatigue]`` request.
    compare : tuple of SimulationResult
        The other families' results drawn beside it in the figures.
    wear : WearReport or None
        The ``[wear]`` history and its assessments at the requested N.
    phases : dict
        Wall time of each phase in seconds (build, solve, compare, fatigue); the writers add
        theirs in summary.json.
    """

    result: object
    reason: str | None = None
    stress: object = None
    fatigue: object = None
    compare: tuple = ()
    wear: object = None
    phases: dict = attrs.field(factory=dict)

    def __repr__(self) -> str:
        carried = (("stress request", self.stress), ("fatigue", self.fatigue), ("wear", self.wear))
        extra = "".join(f", {n}" for n, v in carried if v is not None)
        return f"<RunResult {self.result!r}{extra}>"

    def _repr_html_(self) -> str:
        parts = [self.result._repr_html_()]
        if self.fatigue is not None:
            parts.append(self.fatigue._repr_html_())
        if self.reason:
            parts.append(f"<div>no closed form: {html.escape(self.reason)}</div>")
        return "".join(parts)

    def to_xarray(self):
        """The run's result as an :class:`xarray.Dataset` (``result.to_xarray()``)."""
        return self.result.to_xarray()

    def write(self, out, **options) -> Path:
        """``write_results`` of this run (options: writers, overwrite, steps, figures, vtk,
        progress); summary.json gets the run's phases and the writers' times."""
        return write_results(
            self.result, out, compare=self.compare, stress=self.stress, fatigue=self.fatigue,
            wear=self.wear, phases={**self.phases, **options.pop("phases", {})}, **options,
        )  # fmt: skip


def requests(extras: Mapping | None) -> tuple:
    """The scene's ``[stress]`` and ``[fatigue]`` requests, parsed before any computation."""
    extras = extras or {}
    if "stress" not in extras and "fatigue" not in extras:
        return None, None
    return analyses().requests(extras)


def wear_request(extras: Mapping | None):
    """The scene's ``[wear]`` request (None without one), parsed before any computation."""
    extras = extras or {}
    return analyses().wear_request(extras) if "wear" in extras else None


def _wear_mesh(mode: accuracy.Accuracy) -> None:
    if mode.mesh != "fixed":
        raise InputError(
            "[wear] needs a fixed contact mesh: the worn profile lives on the pairs, which "
            'the adaptive mode changes between levels; set [contact] mesh = "fixed"'
        )


def _cycle_bar(bars, total: int):
    """A ``progress(N, cycles)`` hook advancing a bar over the wear cycles (None: no bar)."""
    if bars is None:
        return None
    bar, done = bars("wear cycles", total), [0]

    def hook(n: int, cycles: int) -> None:
        bar.update(max(int(n) - done[0], 0))
        done[0] = max(done[0], int(n))
        if n >= cycles:
            bar.close()

    return hook


def run_wear_request(
    simulation, request, fatigue_request, mode, say=_quiet, bars=None, sliding=False,
    frame="local",
):  # fmt: skip
    """The ``[wear]`` history of ``simulation`` and its assessments (stresses are evaluated
    when written, fatigue here) at the request's ``assess`` N; ``bars`` draws a bar over the
    cycles; ``sliding``: with finite sliding (``[contact] sliding``), ``frame`` its pair
    frame along an arc (``[contact] frame``)."""
    _wear_mesh(mode)
    wear = request.simulation(simulation, sliding=sliding, frame=frame)
    say(f"wear: {wear.cycles} cycles of steps {[s.name for s in wear.cycle_steps]}")
    result, assessed = analyses().wear_of(
        wear, request, fatigue_request, progress=_cycle_bar(bars, wear.cycles)
    )
    say(f"wear: {result.simulated} cycles simulated, {len(result.jumps)} jumps")
    return assessed


def check_requests(simulation, stress, fatigue) -> None:
    """Refuse stress and fatigue requests too large for the machine, with the estimate."""
    if stress is not None or fatigue is not None:
        analyses().check_requests(simulation, stress, fatigue)


def sliding_blocker(mode: accuracy.Accuracy, extras: Mapping | None) -> None:
    """Refuse what a finite-sliding run cannot do, naming the scene key."""
    if mode.mesh != "fixed":
        raise InputError(
            "[contact] sliding = true needs mesh = 'fixed': the adaptive mode refines the "
            "faces about a contact that does not move; set [contact] mesh = 'fixed'"
        )
    fatigue = (extras or {}).get("fatigue")
    if isinstance(fatigue, Mapping) and "map_x" not in fatigue:
        raise InputError(
            "[fatigue] on a finite-sliding run ([contact] sliding = true) needs map_x: the "
            "default map (+-1.5 a about x = 0) covers only where the pad started; give "
            "[fatigue] map_x = [x_min, x_max] (mm) covering the track"
        )


def _fallback(simulation):
    return with_fallback(simulation) or simulation


def run_simulation(
    simulation,
    *,
    mode: accuracy.Accuracy | None = None,
    extras: Mapping | None = None,
    reason: str | None = None,
    companion: Callable[[int], object] | None = None,
    compare: Sequence = (),
    progress=None,
    say: Callable[[str], None] = _quiet,
    bars=None,
    phases: Mapping | None = None,
    sliding: bool = False,
    memo=None,
    frame: str = "local",
) -> RunResult:
    """Solve ``simulation`` in ``mode``, check it, solve ``compare`` (simulations), and carry
    out the ``extras``' stress and fatigue requests. Raises the failed check's error.
    ``sliding`` runs it (and ``compare``) with finite sliding (``[contact] sliding``),
    ``frame`` the pair frame along an arc (``[contact] frame``).

    ``progress(k, n, step)`` follows the steps; ``bars(description, total)`` makes the
    progress bars of the adaptive levels and the fatigue assessment; ``phases`` are earlier
    phases' seconds (e.g. the build), kept with this run's in ``RunResult.phases``;
    ``memo`` (a :class:`~fretbem.solvers.step_memo.StepMemo`, for the cases of a sweep)
    lends the load steps earlier runs on the same problem solved."""
    mode = mode or accuracy.Accuracy()
    if sliding:
        sliding_blocker(mode, extras)
    if mode.mesh == "adaptive":
        blocker = accuracy.adaptive_blocker(simulation)
        if blocker is not None:
            raise InputError(blocker)
        say(f"adaptive mesh: tolerance {100 * mode.tolerance:g} %, at most {mode.budget} pairs")
    stress, fatigue_request = requests(extras)
    wear = wear_request(extras)
    if wear is not None:  # its laws, cycle and outputs checked against the history now
        _wear_mesh(mode)
        wear.simulation(simulation, sliding=sliding, frame=frame)
    check_requests(simulation, stress, fatigue_request)  # refused before any solve
    # one resource block from the solve to the wear: checked once, and a large run's freed
    # arrays kept for the next phase's
    with run_resources(simulation):
        timed = dict(phases or {})
        options = {} if progress is None else {"progress": progress}
        if bars is not None:
            options["bars"] = bars
        tic = time.perf_counter()
        try:
            if sliding:
                result = solve_sliding(simulation, say=say, progress=progress, frame=frame)
            else:
                result = accuracy.solve(simulation, mode, coarse=companion, memo=memo, **options)
        except SolverConvergenceError as failure:
            # (a rotating block that tips has no answer for Lemke's method either)
            tipped = sliding or isinstance(failure, BlockTippingError)
            retry = None if tipped else with_fallback(simulation)
            if retry is None:
                raise
            say(f"Newton did not converge ({str(failure).split(';')[0]}); solving again with "
                "Lemke's method on the increments Newton fails on")  # fmt: skip
            coarse = None if companion is None else (lambda n: _fallback(companion(n)))
            result = accuracy.solve(retry, mode, coarse=coarse, **options)
        # a failed check ends here: nothing is post-processed or written (the run checked each
        # step as it solved it: only the consistency of the result is left)
        check_steps(result, fresh=True)
        timed["solve"] = time.perf_counter() - tic
        others = []
        if compare:
            tic = time.perf_counter()
            for other in compare:
                say("running a comparison family")
                others.append(
                    solve_sliding(other, say=_quiet, frame=frame) if sliding else run(other)
                )
                check_steps(others[-1])
            timed["compare"] = time.perf_counter() - tic
        fatigue = None
        if fatigue_request is not None:
            say("fatigue assessment")
            tic = time.perf_counter()
            fatigue = analyses().fatigue_of(result, fatigue_request, progress=bars)
            timed["fatigue"] = time.perf_counter() - tic
        worn = None
        if wear is not None:
            tic = time.perf_counter()
            worn = run_wear_request(
                simulation, wear, fatigue_request, mode, say, bars, sliding, frame
            )
            timed["wear"] = time.perf_counter() - tic
        return RunResult(result, reason, stress, fatigue, tuple(others), wear=worn, phases=timed)


def run_scene(
    scene,
    *,
    mode: accuracy.Accuracy | None = None,
    compare: Sequence[str] = (),
    progress=None,
    say: Callable[[str], None] = _quiet,
    bars=None,
    **contact,
) -> RunResult:
    """Run a :class:`~fretbem.scenes.spec.Scene` as ``fretbem run`` does (before writing).

    ``mode`` defaults to the scene's (``[contact] mesh``, tolerance, budget, estimate);
    ``compare`` names other basis families solved for the figures; ``contact`` overrides
    ``[contact]`` keys (e.g. ``pairs=121``).
    """
    tic = time.perf_counter()
    simulation, reason = build(scene, **contact)
    built = time.perf_counter() - tic
    sliding = scene.contact.sliding
    if sliding:
        reason = "finite sliding: no closed form follows the pad along the track"
    return run_simulation(
        simulation,
        mode=mode or accuracy.mode_of(scene),
        extras=scene.extras,
        reason=reason,
        companion=lambda pairs: build(scene, **{**contact, "pairs": pairs})[0],
        compare=[build(scene, **{**contact, "basis": name})[0] for name in compare],
        progress=progress,
        say=say,
        bars=bars,
        phases={"build": built},
        sliding=sliding,
        frame=scene.contact.sliding_frame,
    )
