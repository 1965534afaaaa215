"""Finite sliding: a history in which the pad slides along the specimen, re-paired as it goes.

The history is an ordinary one (:class:`~fretbem.simulation.LoadStep`); a step that drives
the pad's block by displacement (``delta``) can carry it any distance, in gross slip
(Q = f P) as far as the faces reach. Before every increment in which the pad's face would
end more than one pair spacing from where its pairs were projected, the pairs are projected
again where the face is (:class:`~fretbem.contact.node_to_segment.NodeToSegmentPair` with
its ``offset``): the face's slide (the pairs' relative tangential displacement, weighted by
pressure) goes into the offset (the geometry), and out of the block unknown, so the problem
stays small-displacement about the current configuration. The block's own displacement is
not the face's: a finite pad's block runs ahead of its face by the bodies' elastic give
under Q, and moving the geometry by it would slide the pairs where no point has slid.

The law's memory is carried to the new pairing: the pair tractions live on the slave face,
whose nodes the new pairing keeps, and the stick reference (the previous relative
tangential displacement) is the previous state seen through the new pairing with the pad
where it physically was, so no slip is invented or lost by re-pairing. Points of the other
face that come into contact for the first time are reported, once per step.

The track is the specimen's face (:class:`~fretbem.sliding.track.Track`): straight, the pad
offset along it; or a circular arc (a convex or concave cylindrical specimen), the pad
turned about the arc's centre by s / R as it slides, so it stays on the arc and normal to
it, with the pair frame turning with it and P and Q along the local normal and tangent. A
block that rotates does so about the pivot, a point of the pad in its own axes, by its tilt
theta from the pad's pose (turned along an arc), carried unchanged by each re-pairing.

Both body models slide. On finite ``bem`` bodies the pressure's centre runs ahead of the
pad's axis in the sense of Q (0.134 mm on the reference scene's 6.5 mm pad at Q = f P): the
pad bends under Q as a cantilever held by its block and its tilted cylinder touches off its
axis. The same bodies without sliding show the same shift (docs/explanation/pairing.rst).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import attrs
import numpy as np

from fretbem.contact import control
from fretbem.contact.law import ContactState, PairState
from fretbem.contact.node_to_segment import FRAMES, NodeToSegmentPair
from fretbem.contact.pairs import ContactDiscretisationError
from fretbem.errors import InputError
from fretbem.results import IncrementRecord, StepResult
from fretbem.simulation import (
    Simulation,
    check_balance,
    check_tilt,
    loads_between,
    no_balance,
    run_resources,
)
from fretbem.solvers.newton import SolverConvergenceError
from fretbem.validators import flag, real_number
from fretbem.verification.checks import check_step

from .track import Track, TrackError

__all__ = ["SlidingError", "SlidingResult", "run_sliding"]


class SlidingError(InputError):
    """A sliding history that cannot be run (wrong pairing, a slide off the faces)."""


@attrs.frozen(eq=False)
class SlidingResult:
    """Every step's result, where the pad was and the pair it was solved with.

    Attributes
    ----------
    steps : tuple of StepResult
        Per step; ``x`` are the pair positions on the lower face where the pad was then.
    offsets : tuple of float
        The pad's slide (mm along the track: the tangent, or the arc's length) carried in
        the pairing at each step's end.
    positions : tuple of float
        The pad block's tangential displacement at each step's end (mm): offset plus the
        block unknown (along the pad's own tangent), the delta of displacement control.
    pairs : tuple of NodeToSegmentPair
        The pairing at the end of each step.
    notes : tuple of str
        What the run reported: new points coming into contact.
    repairings : int
        How many times the faces were paired again.
    simulation : Simulation or None
        The simulation as run: its pairs on the pad's nodes, a rotating block's pivot
        pinned where the pad started (:meth:`~fretbem.simulation.Simulation.pinned`).
    """

    steps: tuple[StepResult, ...]
    offsets: tuple[float, ...]
    positions: tuple[float, ...]
    pairs: tuple[NodeToSegmentPair, ...]
    notes: tuple[str, ...]
    repairings: int
    simulation: Simulation | None = None

    def __getitem__(self, name: str) -> StepResult:
        for step in self.steps:
            if step.name == name:
                return step
        raise KeyError(f"no step {name!r}; steps are {[s.name for s in self.steps]}")


def _repaired(pair: NodeToSegmentPair, offset: float, track, step: str, states):
    """The pair projected again with the upper body slid ``offset`` along ``track`` (a
    :class:`~fretbem.sliding.track.Track`, or the tangent of a straight one); a pair in
    contact that the other face no longer reaches is an error."""
    if isinstance(track, Track):
        moved = track.placed(pair, offset)
    else:
        moved = attrs.evolve(pair, offset=offset * track, uncovered="open")
    try:
        moved.pairing()
    except ContactDiscretisationError as err:
        raise SlidingError(f"step {step!r}: at a slide of {offset:.6g} mm: {err}") from None
    lost = ~moved.covered() & (states != PairState.SEPARATED)
    if lost.any():
        where = moved.pairing().points[lost][0].round(6)
        raise SlidingError(
            f"step {step!r}: at a slide of {offset:.6g} mm the pair in contact at {where} has "
            "slid past the end of the other face: the faces no longer cover the contact; "
            "lengthen the face the other slides along (its contact segment: in a scene file "
            "a wider [contact] track_width, or omit it for the zone plus the largest delta) "
            "to cover the whole track, or slide less"
        )
    return moved


def _carried(state: ContactState, problem, shift: np.ndarray) -> ContactState:
    """``state`` seen through a new pairing of the same slave nodes whose geometry carries
    the pad ``shift`` further: the block unknown gives that much back (the pad stays where
    it is), the tractions stay, the stick reference is recomputed with the new pairing."""
    if state.virgin:
        return ContactState.initial(problem)
    x = np.array(state.x, dtype=float)
    x[problem.layout.block("upper")] -= shift
    slip = problem.relative_tangential(x, problem.amplitudes(state.loads))
    return attrs.evolve(state, x=x, slip=slip)


def _block_delta(problem, x: np.ndarray) -> float:
    """The pad block's tangential displacement against the datum, in the current geometry."""
    return float(control.motion_rows(problem)[1] @ x)


def _face_slide(problem, state: ContactState) -> float:
    """How far the pad's face has slid along the other face since the pairs were projected:
    the relative tangential displacement of the pairs in contact, weighted by their
    pressure. Not the block's displacement: a finite pad's block runs ahead of its face by
    the bodies' elastic give under Q (0.026 mm at Q = 30 N/mm on the reference scene's
    bodies), which no pair has slid. With no pair in contact the pad is unloaded and its
    face moves with its block."""
    pressure = np.maximum(problem.unknowns(state.x).pressure, 0.0)
    if not pressure.sum() > 0.0:
        return _block_delta(problem, state.x)
    return float(np.sum(pressure * state.slip) / pressure.sum())


def _loaded(pair: NodeToSegmentPair, states: np.ndarray, track: Track | None = None):
    """The master face (label) and which of its nodes lie within the contact: between the
    outermost pairs not separated (positions along ``track``; None: a straight one)."""
    pairing = pair.pairing()
    master = "upper" if pair.slave_side() == "lower" else "lower"
    touching = pairing.points[states != PairState.SEPARATED]
    if track is None or track.straight:
        body, tag = pair.side(master)
        tangent = pairing.tangents[0]
        along = body.contact_face(tag).points @ tangent
        if master == "upper":
            along = along + pair.offset @ tangent
        touching = touching @ tangent
    else:
        along, touching = track.along(pair.placed(master)), track.along(touching)
    if touching.size == 0:
        return master, np.zeros(along.shape, dtype=bool)
    return master, (along >= touching.min()) & (along <= touching.max())


def _slid(record, offset: float):
    """A step's or an increment's record with the slide carried in the pairing added back:
    the block's delta and the relative tangential displacement (upper minus lower) are
    counted from where the pad started, not from the step's pairing."""
    if isinstance(record, StepResult):
        slip = record.tangential_displacement + offset
        return attrs.evolve(record, delta=record.delta + offset, tangential_displacement=slip)
    return attrs.evolve(record, delta=record.delta + offset, slip=record.slip + offset)


def _on_the_pad(pair: NodeToSegmentPair) -> NodeToSegmentPair:
    """The pair with its pairs on the pad's nodes: they move with the pad and the track
    faces them all the way, and the memory is carried on them. The default rule (the
    coarser face) would stand them on the specimen when its face has fewer nodes, whose
    nodes along the track beyond the pad face nothing; a pair set on the specimen is refused."""
    if pair.slave == "coarser":
        return attrs.evolve(pair, slave="upper") if pair.slave_side() == "lower" else pair
    if pair.slave == "lower":
        raise SlidingError(
            "finite sliding keeps its pairs on the pad's nodes (they move with the pad and the "
            "track faces them as it slides), but the pair has slave = 'lower' (the specimen's "
            "nodes); use NodeToSegmentPair(..., slave='upper') or the default 'coarser'"
        )
    return pair


def condenser(simulation: Simulation) -> Callable:
    """How a sliding run condenses each pairing: the pair's own problem, or, for a block
    that rotates (:attr:`~fretbem.simulation.Simulation.rotates`), with the rotation about
    the pivot pinned where the pad starts (a point of the pad, in its own axes, so every
    pairing carries the same pivot as the pad slides: :meth:`Simulation.pinned`). Along an
    arc the pad's own axes turn with it: theta is its tilt from that turned pose, and the
    rotation's rows are taken in those axes (docs/explanation/pairing.rst)."""
    if not simulation.rotates:
        return simulation.condense
    check_balance(simulation, simulation.prepare())
    return simulation.condense


def _spacing(pair: NodeToSegmentPair) -> float:
    points = pair.pairing().points
    return float(np.min(np.linalg.norm(np.diff(points, axis=0), axis=1)))


def run_sliding(
    simulation: Simulation,
    *,
    every: float = 1.0,
    check: bool = True,
    note: Callable[[str], None] | None = print,
    progress: Callable | None = None,
    frame: str = "local",
) -> SlidingResult:
    """Step ``simulation`` through its history, re-pairing as the pad slides.

    The pair must be a :class:`~fretbem.contact.node_to_segment.NodeToSegmentPair` and the
    pad must carry the loading block. The faces are paired again before an increment that
    would leave the pad more than ``every`` pair spacings from where its pairs were
    projected (0: whenever it moves at all). No closed form applies to a sliding contact, so
    the steps carry no errors against theory. ``note`` receives each message about new
    points in contact (None: collect only); ``progress(k, n, step)`` is called after each
    step. ``frame``: the pair frame along an arc, ``"local"`` (default: each pair's own,
    the arc's normal where it meets it) or ``"shared"`` (all pairs the pad's turned frame,
    the a/R simplification; :class:`~fretbem.contact.node_to_segment.NodeToSegmentPair`'s
    ``frame``); a straight track's pairs share one frame either way.
    """
    if frame not in FRAMES:
        raise SlidingError(
            f"run_sliding frame must be one of {FRAMES}, got {frame!r}; give 'local' (each "
            "pair its own frame along an arc) or 'shared' (the pad's turned frame)"
        )
    every = real_number(
        "every",
        every,
        what="pair spacings the pad may move before its faces are re-paired",
        fix="give e.g. 1.0 (0: re-pair before every increment that moves the pad)",
        error=SlidingError,
    )
    if not every >= 0.0:
        raise SlidingError(f"every must be a number of pair spacings >= 0, got {every!r}")
    check = flag("check", check, error=SlidingError)
    pair = simulation.pair
    if not isinstance(pair, NodeToSegmentPair):
        raise SlidingError(
            f"finite sliding re-pairs the faces by projection, but the pair is a "
            f"{type(pair).__name__}; use NodeToSegmentPair ([contact] pairing = "
            "'node-to-segment')"
        )
    with run_resources(simulation):
        return _slide(simulation, pair, every, check, note, progress, frame)


def _slide(simulation, pair, every, check, note, progress, frame) -> SlidingResult:
    """:func:`run_sliding` after its arguments' checks, in the run's resource block."""
    pair = _on_the_pad(pair)
    try:
        track = Track.of(pair)
    except TrackError as err:
        raise SlidingError(str(err)) from None
    if not track.straight:  # the pairs spread over a turning face: each its own frame
        pair = attrs.evolve(pair, frame=frame)
    simulation = attrs.evolve(simulation, pair=pair, reference=None).pinned()
    condensed, first = condenser(simulation), pair
    tangent = track.tangent
    offset = track.slide_of(pair)
    spacing = _spacing(pair)
    problem = condensed(pair)
    state = ContactState.initial(problem)
    friction = getattr(simulation.law, "friction", float("nan"))
    master, seen = _loaded(pair, state.states, track)
    notes: list[str] = []
    results, offsets, positions, pairs, history = [], [], [], [], []
    repairings = 0
    for load in simulation.steps:
        controls = load.controls
        tic, iterations, residuals = time.perf_counter(), 0, []
        fresh = np.zeros_like(seen)
        start_n, start_t, start_r = simulation._start(problem, state, controls)
        if controls.tangential == "displacement":
            start_t += offset  # delta where the pad physically is
        start_loads = dict(state.loads)
        increments: list[IncrementRecord] = []
        for k in range(1, load.increments + 1):
            frac = k / load.increments
            target_n = start_n + frac * (load.normal_target - start_n)
            target_t = start_t + frac * (load.tangential_target - start_t)
            target_r = start_r + frac * (load.rotation_target - start_r)
            loads = loads_between(start_loads, load.loads, frac)
            # where the pad's face will be (delta-driven: the block's coming move on top of
            # the face's slide so far) or is (force-driven), against the pairing
            ahead = 0.0 if state.virgin else _face_slide(problem, state)
            if controls.tangential == "displacement" and not state.virgin:
                ahead += target_t - offset - _block_delta(problem, state.x)
            if abs(ahead) > every * spacing and ahead != 0.0:
                offset += ahead
                pair = _repaired(pair, offset, track, load.name, state.states)
                shift = ahead * tangent
                if not track.straight and not state.virgin:  # the block turns with the pad
                    block = state.x[problem.layout.block("upper")]
                    shift = block - track.carried(pair, block, ahead)
                problem = condensed(pair)
                state = _carried(state, problem, shift)
                simulation = attrs.evolve(simulation, pair=pair)
                repairings += 1
            driven_t = target_t - offset if controls.tangential == "displacement" else target_t
            try:
                state, its, res = simulation._increment(
                    problem, state, target_n, driven_t, loads, controls=controls,
                    rotation=target_r,
                )  # fmt: skip
            except SolverConvergenceError as failure:
                if not simulation.rotates:
                    raise
                message = no_balance(simulation, problem, load, failure)
                raise SolverConvergenceError(message, failure.residuals) from None
            check_tilt(simulation, problem, state, load)
            iterations += its
            residuals += res
            increments.append(_slid(IncrementRecord.of(problem, state, simulation.rig), offset))
            master, loaded = _loaded(pair, state.states, track)
            fresh |= loaded & ~seen if seen.any() else np.zeros_like(loaded)
            seen = seen | loaded
        if fresh.any():
            if track.straight:
                body, tag = pair.side(master)
                along = body.contact_face(tag).points[fresh] @ tangent
                if master == "upper":
                    along = along + offset
            else:
                along = track.along(pair.placed(master)[fresh])
            message = (
                f"step {load.name!r}: {int(fresh.sum())} new point(s) of the {master} face came "
                f"into contact, from {along.min():.4g} to {along.max():.4g} mm along the surface "
                f"(the pad's face at {offset + _face_slide(problem, state):.4g} mm, its block "
                f"at {offset + _block_delta(problem, state.x):.4g} mm)"
            )
            notes.append(message)
            if note is not None:
                note(message)
        history.append(load.tangential if load.delta is None else state.tangential)
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
        # the block's delta and the slip counted from where the pad started; the checks read
        # none of the fields the last record changes (its increments and pairing)
        slid = _slid(result, offset)
        checks = check_step(slid, friction) if check else None
        result = attrs.evolve(slid, increments=tuple(increments), pair=pair, checks=checks)
        results.append(result)
        offsets.append(offset)
        positions.append(offset + _block_delta(problem, state.x))
        pairs.append(pair)
        if progress is not None:
            progress(len(results), len(simulation.steps), result)
    return SlidingResult(
        tuple(results), tuple(offsets), tuple(positions), tuple(pairs), tuple(notes), repairings,
        attrs.evolve(simulation, pair=first),
    )  # fmt: skip
