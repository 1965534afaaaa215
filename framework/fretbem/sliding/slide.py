"""A load history in which the upper body slides along the lower one: re-pair as it goes.

Each :class:`SlideStep` is a load step plus a slide: the distance the upper body is carried
rigidly along the pair tangent over the step (mm), in equal parts over its increments.
Under force control a body in gross slip has no equilibrium position (|Q| = f P leaves the
block's tangential position undetermined), so the slide is given, and each increment then
solves the contact at the step's P and Q (Q just below f P keeps the contact in slip over
all but a small stick zone).

At every increment the pair is projected again at the new position
(:class:`~fretbem.contact.node_to_segment.NodeToSegmentPair` with its ``offset``) and the
law's memory is carried over: the pair tractions live on the slave face, whose nodes the
new pairing keeps, and the previous relative tangential displacement (the stick reference)
is that of the previous state seen through the new pairing, the block where it was: the
slide counts as slip already done, so the contact does not spring back over it (what a
body in gross slip does; a displacement-controlled history would find it instead of being
given it). Points of the other face that take load for the first time in a step are
reported once per step (a note through ``note``), so a slide that brings new surface into
contact says so.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import attrs
import numpy as np

from fretbem.contact.law import ContactState, PairState
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairs import ContactDiscretisationError
from fretbem.errors import InputError
from fretbem.results import StepResult
from fretbem.simulation import LoadStep, Simulation
from fretbem.verification.checks import check_step

__all__ = ["SlideStep", "SlidingError", "SlidingResult", "run_sliding"]


class SlidingError(InputError):
    """A sliding history that cannot be run (wrong pairing, a slide off the faces)."""


@attrs.frozen
class SlideStep:
    """A load step and the slide of the upper body over it.

    Attributes
    ----------
    load : LoadStep
        P, Q (and named loads) at the end of the step, and its increments.
    slide : float
        Rigid displacement of the upper body along the pair tangent over the step (mm);
        0 for a step in place.
    """

    load: LoadStep
    slide: float = attrs.field(default=0.0, converter=float)


@attrs.frozen(eq=False)
class SlidingResult:
    """Every step's result, the offset reached and the pair it was solved with.

    Attributes
    ----------
    steps : tuple of StepResult
    offsets : tuple of float
        The upper body's slide so far at the end of each step (mm, along the tangent).
    pairs : tuple of NodeToSegmentPair
        The pairing at the end of each step (its ``offset``).
    notes : tuple of str
        What the run reported: new points coming into contact.
    """

    steps: tuple[StepResult, ...]
    offsets: tuple[float, ...]
    pairs: tuple[NodeToSegmentPair, ...]
    notes: tuple[str, ...]

    def __getitem__(self, name: str) -> StepResult:
        for step in self.steps:
            if step.name == name:
                return step
        raise KeyError(f"no step {name!r}; steps are {[s.name for s in self.steps]}")


def _repaired(pair: NodeToSegmentPair, offset: float, tangent: np.ndarray, step: str):
    """The pair projected again with the upper body ``offset`` along the tangent."""
    moved = attrs.evolve(pair, offset=offset * tangent)
    try:
        moved.pairing()
    except ContactDiscretisationError as err:
        raise SlidingError(
            f"step {step!r}: at a slide of {offset:.6g} mm the faces no longer cover each "
            f"other ({err}); lengthen the face the other slides along (its contact segment, "
            "e.g. a wider [contact] zone_width) to cover the whole track, or slide less"
        ) from None
    return moved


def _carried(state: ContactState, problem) -> ContactState:
    """``state`` seen through a new pairing of the same slave nodes: the tractions and the
    block as they were, the stick reference recomputed with the new pairing."""
    if state.virgin:
        return ContactState.initial(problem)
    _, slip = problem.relative(state.x, problem.amplitudes(state.loads))
    return attrs.evolve(state, slip=slip)


def _loaded(pair: NodeToSegmentPair, states: np.ndarray) -> tuple[str, np.ndarray]:
    """The master face (label) and which of its nodes lie within the contact: between the
    outermost pairs not separated (a node is in contact where the pairs around it are)."""
    pairing = pair.pairing()
    master = "upper" if pair.slave_side() == "lower" else "lower"
    body, tag = pair.side(master)
    tangent = pairing.tangents[0]
    along = body.contact_face(tag).points @ tangent
    if master == "upper":
        along = along + pair.offset @ tangent
    touching = pairing.points[states != PairState.SEPARATED] @ tangent
    if touching.size == 0:
        return master, np.zeros(along.shape, dtype=bool)
    return master, (along >= touching.min()) & (along <= touching.max())


def run_sliding(
    simulation: Simulation,
    steps: Sequence[SlideStep],
    *,
    check: bool = True,
    note: Callable[[str], None] | None = print,
) -> SlidingResult:
    """Step ``simulation``'s pair through ``steps``, re-pairing at every slide increment.

    The simulation gives the pair (node to segment), the law and the solver; its own load
    steps are replaced by ``steps`` (the first presses the bodies together, as always).
    No closed form applies to a sliding contact: the steps carry no errors against theory.
    ``note`` receives each message about new points in contact (None: collect only).
    """
    pair = simulation.pair
    if not isinstance(pair, NodeToSegmentPair):
        raise SlidingError(
            f"finite sliding re-pairs the faces by projection, but the pair is a "
            f"{type(pair).__name__}; use NodeToSegmentPair ([contact] pairing = "
            "'node-to-segment')"
        )
    steps = tuple(steps)
    simulation = attrs.evolve(simulation, steps=tuple(s.load for s in steps), reference=None)
    tangent = pair.pairing().tangents[0]
    offset = float(pair.offset @ tangent)
    problem = pair.condensed()
    state = ContactState.initial(problem)
    friction = getattr(simulation.law, "friction", float("nan"))
    master, seen = _loaded(pair, state.states)
    notes: list[str] = []
    results, offsets, pairs, history = [], [], [], []
    for step in steps:
        load = step.load
        iterations, residuals, tic = 0, [], time.perf_counter()
        fresh = np.zeros_like(seen)
        start = (state.normal, state.tangential, dict(state.loads))
        for k in range(1, load.increments + 1):
            frac = k / load.increments
            if step.slide:
                offset += step.slide / load.increments
                pair = _repaired(pair, offset, tangent, load.name)
                problem = pair.condensed()
                state = _carried(state, problem)
                simulation = attrs.evolve(simulation, pair=pair)
            targets = [start[0] + frac * (load.normal - start[0]),
                       start[1] + frac * (load.tangential - start[1])]  # fmt: skip
            loads = {n: start[2].get(n, 0.0) + frac * (v - start[2].get(n, 0.0))
                     for n, v in load.loads.items()}  # fmt: skip
            state, its, res = simulation._increment(problem, state, *targets, loads)
            iterations += its
            residuals += res
            master, loaded = _loaded(pair, state.states)
            fresh |= loaded & ~seen if seen.any() else np.zeros_like(loaded)
            seen = seen | loaded
        if fresh.any():
            body, tag = pair.side(master)
            along = body.contact_face(tag).points[fresh] @ tangent
            if master == "upper":
                along = along + offset
            message = (
                f"step {load.name!r}: {int(fresh.sum())} new point(s) of the {master} face came "
                f"into contact, from {along.min():.4g} to {along.max():.4g} mm along the surface "
                f"(slide {offset:.4g} mm)"
            )
            notes.append(message)
            if note is not None:
                note(message)
        history.append(load.tangential)
        result = StepResult.build(
            simulation,
            problem,
            load,
            state,
            iterations,
            residuals,
            time.perf_counter() - tic,
            tuple(history),
        )
        if check:
            result = attrs.evolve(result, checks=check_step(result, friction))
        results.append(result)
        offsets.append(offset)
        pairs.append(pair)
    return SlidingResult(tuple(results), tuple(offsets), tuple(pairs), tuple(notes))
