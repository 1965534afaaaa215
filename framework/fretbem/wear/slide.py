"""Wear cycles on a sliding contact: the pairing follows the pad, each face wears in place.

A :class:`Track` is where a finite-sliding history stands: the pairing of the moment (a
:class:`~fretbem.wear.track.WornTrackPair` carrying both faces' wear), its condensation and
the simulation solving on it. :meth:`Track.step` advances it through a load step exactly as
:func:`fretbem.sliding.slide.run_sliding` does (the faces projected again whenever the pad
has moved a pair spacing, the friction memory carried to the new pairing), with a hook
after every increment. :func:`simulate_sliding_cycle` uses that hook to wear the faces: a
pair's depth increment goes to each face at the material point the pair meets on it (at the
increment's mid-point), so the specimen's scar spans the contact plus the stroke while the
pad wears at its own points. Which points meet comes from the pair's relative tangential
displacement (the slip plus the elastic part), not from the block's travel, which also
counts the bodies' tangential compliance.

Both body models: the wear enters only the pairs' gap and the material points meet where
the relative displacement puts them, neither of which depends on how the bodies deform. On
finite ``bem`` bodies that relative displacement carries the pad's bending under Q (its
tilted cylinder touches ahead of its axis), so the pad's scar is wider than its contact by
twice that shift and the specimen's by the same, as the bodies really rub
(docs/explanation/wear.rst, measured against half-planes as the bodies grow).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.law import ContactState, PairState
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.simulation import LoadStep, Simulation, check_tilt, loads_between
from fretbem.sliding import track as sliding_track
from fretbem.sliding.slide import (
    SlidingError,
    _block_delta,
    _carried,
    _repaired,
    _spacing,
    condenser,
)

from .cycle import BLOCK_ROTATION, CycleWear
from .law import WearLaw
from .profile import BODIES, WornProfile, pair_weights
from .track import WornTrackPair, spread, track_grids

__all__ = ["Track", "check_pair", "simulate_sliding_cycle"]


def check_pair(pair: NodeToSegmentPair) -> sliding_track.Track:
    """The track of the pair wear with finite sliding takes: straight (either body model)
    or a circular arc (``bem`` bodies; :class:`~fretbem.sliding.track.Track`)."""
    try:
        return sliding_track.Track.of(pair)
    except sliding_track.TrackError as err:
        raise SlidingError(f"wear with finite sliding: {err}") from None


def _check_slave(pair: NodeToSegmentPair, grids: dict) -> None:
    """Each node of the face the pairs stand on must be faced by the other face at the
    start: its depth is its pairs' wear over the face length it stands for, which an
    unfaced node (a specimen's node along the track beyond the pad) does not have."""
    slave = pair.slave_side()
    unfaced = grids[slave][1] <= 0.0
    if unfaced.any():
        role = "pad" if slave == "upper" else "specimen"
        raise SlidingError(
            f"wear with finite sliding keeps each pair on a node of the {role} (the pair's "
            f"slave face), but {int(unfaced.sum())} of its nodes are not faced by the other "
            "face at the start, so their wear has no face length to be spread over; pair on "
            "the pad's nodes, NodeToSegmentPair(slave='upper') (a scene file's sliding pair "
            "always does)"
        )


@attrs.frozen(eq=False)
class Track:
    """A sliding contact where it stands: the simulation on the pairing of the moment.

    Attributes
    ----------
    simulation : Simulation
        Its pair is the current :class:`~fretbem.wear.track.WornTrackPair`.
    problem : CondensedContact
        That pair's condensation.
    tangent : ndarray
        The track's direction where the pad starts.
    spacing : float
        The pairs' spacing (mm): the faces are projected again when the pad has moved more.
    pairings : dict
        The pairings met so far by slide (in millionths of a spacing): a cycle visits the
        same slides every time, and a projection and condensation cost far more than the
        increments solved on them (60 ms against 5 ms measured on half-planes, 41 pairs).
    path : fretbem.sliding.track.Track
        The specimen's face the pad slides along (:class:`~fretbem.sliding.track.Track`):
        straight, or a circular arc the pad turns along, each pair in its own frame (the
        worn depth is a gap along each pair's normal) and positions in arc length.
    """

    simulation: Simulation
    problem: CondensedContact
    tangent: np.ndarray
    spacing: float
    pairings: dict = attrs.field(factory=dict)
    path: sliding_track.Track | None = None

    @classmethod
    def start(cls, simulation: Simulation, frame: str = "local") -> Track:
        """The unworn contact of ``simulation`` (node-to-segment pairing, a straight or
        circular track; a rotating block turns about the pivot of this first pairing, a
        point of the pad carried along the track), before any step; along an arc the pairs
        take ``frame`` ("local": each its own, "shared": the pad's turned frame)."""
        pair = simulation.pair
        if not isinstance(pair, NodeToSegmentPair):
            raise SlidingError(
                f"wear with finite sliding re-pairs the faces by projection, but the pair is "
                f"a {type(pair).__name__}; use NodeToSegmentPair ([contact] pairing = "
                "'node-to-segment')"
            )
        path = check_pair(pair)
        simulation = simulation.pinned()  # a rotating block keeps the first pairing's pivot
        if not path.straight:  # along an arc: each pair its own frame, or the pad's
            pair = attrs.evolve(pair, frame=frame)
        if not isinstance(pair, WornTrackPair):
            grids = track_grids(pair, pair_weights(pair.condensed()), path)
            _check_slave(pair, grids)
            zero = {body: np.zeros(grids[body][0].size) for body in BODIES}
            pair = WornTrackPair.of(pair, grids, zero["upper"], zero["lower"], path)
        simulation = attrs.evolve(simulation, pair=pair, reference=None)
        problem = condenser(simulation)(pair)
        return cls(simulation, problem, path.tangent, _spacing(pair), path=path)

    def condensed(self, pair: WornTrackPair) -> CondensedContact:
        """``pair``'s condensation, with a rotating block's rotation about the pinned pivot."""
        return self.simulation.condense(pair)

    @property
    def pair(self) -> WornTrackPair:
        """The pairing of the moment."""
        return self.simulation.pair

    def unworn(self) -> WornProfile:
        """No wear yet, each face's depth at its own points (:func:`track_grids`)."""
        grids = track_grids(self.pair, pair_weights(self.problem), self.path)
        (upper, up_w), (lower, low_w) = grids["upper"], grids["lower"]
        return WornProfile(lower, low_w, np.zeros(upper.size), np.zeros(lower.size),
                           upper_x=upper, upper_weights=up_w)  # fmt: skip

    def worn(self, profile: WornProfile) -> Track:
        """The same pairing with the faces worn to ``profile`` (its grid)."""
        pair = self.pair.rewear(profile.upper, profile.lower)
        return attrs.evolve(
            self, simulation=attrs.evolve(self.simulation, pair=pair), problem=self.condensed(pair)
        )

    def block(self, state: ContactState) -> float:
        """How far the pad's block has moved along the track beyond the pairing's slide."""
        return 0.0 if state.virgin else _block_delta(self.problem, state.x)

    def along(self) -> np.ndarray:
        """The pairs' points along the track in this pairing (mm)."""
        if self.path is None or self.path.straight:
            return self.problem.pairing.points @ self.tangent
        return self.path.along(self.problem.pairing.points)

    def positions(self, state: ContactState) -> np.ndarray:
        """The pairs' positions on the specimen (mm along its face) at ``state``."""
        return self.pair.material(self.along(), np.asarray(state.slip))["lower"]

    def _moved(self, ahead: float, state: ContactState, name: str):
        slide = self.pair.slide() + ahead
        key = round(slide / self.spacing * 1e6)
        known = self.pairings.get(key)
        if known is not None:
            pair = known.rewear(self.pair.upper_wear, self.pair.lower_wear)
            ahead = pair.slide() - self.pair.slide()  # within a millionth of a spacing
            if np.any(~pair.covered() & (state.states != PairState.SEPARATED)):
                known = None  # let the projection name the pair that slid off the face
        if known is None:
            pair = _repaired(self.pair, slide, self.path or self.tangent, name, state.states)
            ahead = slide - self.pair.slide()
            self.pairings[key] = pair
        problem = self.condensed(pair)
        shift = ahead * self.tangent
        if self.path is not None and not self.path.straight and not state.virgin:
            block = state.x[problem.layout.block("upper")]  # the block turns with the pad
            shift = block - self.path.carried(pair, block, ahead)
        state = _carried(state, problem, shift)
        touching = state.states != PairState.SEPARATED
        if touching.any():  # where the pad's surface is against its block's travel
            pair = pair.rewear(pair.upper_wear, pair.lower_wear, float(state.slip[touching].mean()))
            problem = self.condensed(pair)
        track = attrs.evolve(self, simulation=attrs.evolve(self.simulation, pair=pair),
                             problem=problem)  # fmt: skip
        return track, state

    def step(
        self, state: ContactState, load: LoadStep, record: Callable | None = None
    ) -> tuple[Track, ContactState, int]:
        """Advance through ``load`` re-pairing as the pad slides; ``record(track, before,
        after)`` is called after every increment with the pairing it was solved on and the
        states at its start (as carried to that pairing) and end. Returns the track, the
        state and the Newton iterations."""
        track, controls, iterations = self, load.controls, 0
        displacement = controls.tangential == "displacement"
        start_n, start_t, start_r = track.simulation._start(track.problem, state, controls)
        if displacement:
            start_t += track.pair.slide()  # delta where the pad physically is
        start_loads = dict(state.loads)
        for k in range(1, load.increments + 1):
            frac = k / load.increments
            target_n = start_n + frac * (load.normal_target - start_n)
            target_t = start_t + frac * (load.tangential_target - start_t)
            target_r = start_r + frac * (load.rotation_target - start_r)
            loads = loads_between(start_loads, load.loads, frac)
            ahead = track.block(state)
            if displacement and not state.virgin:
                ahead = target_t - track.pair.slide()
            if abs(ahead) > track.spacing and ahead != 0.0:
                track, state = track._moved(ahead, state, load.name)
            driven_t = target_t - track.pair.slide() if displacement else target_t
            before = state
            state, its, _ = track.simulation._increment(
                track.problem, state, target_n, driven_t, loads, controls=controls,
                rotation=target_r,
            )  # fmt: skip
            check_tilt(track.simulation, track.problem, state, load)
            iterations += its
            if record is not None:
                record(track, before, state)
        return track, state, iterations


def simulate_sliding_cycle(
    track: Track,
    state: ContactState,
    cycle: Sequence[LoadStep],
    laws: Mapping[str, WearLaw],
    profile: WornProfile,
) -> tuple[CycleWear, Track]:
    """Solve ``cycle`` from ``track`` and ``state``; the wear it causes, each face's on
    ``profile``'s grid (depth, energy and work there; the pressure sensitivities, p and q
    per pair) and the track at its end."""
    grids = {body: profile.grid(body) for body in BODIES}
    slave = track.pair.slave_side()
    n = track.problem.n_pairs
    depth = {body: np.zeros(grids[body][0].size) for body in BODIES}
    sensitivities = {body: np.zeros(n) for body in BODIES}
    energy, energy_sensitivity, work, work_sensitivity = (
        np.zeros(profile.x.size) for _ in range(4)
    )
    path = np.zeros(n)
    pressures, shears, positions, turns, iterations = [], [], [], [], 0

    def place(body, now, before, after, w, volume):
        """Depth on ``body``'s points of the pairs' ``volume``: at the slave's own nodes,
        spread over what the pairs swept on the other face."""
        x, weights = grids[body]
        if body == slave:
            return volume / weights
        start = now.pair.material(now.along(), np.asarray(before.slip))[body]
        end = now.pair.material(now.along(), np.asarray(after.slip))[body]
        return spread(x, weights, start, end, w, volume)

    def wear(now: Track, before: ContactState, after: ContactState) -> None:
        layout = now.problem.layout
        ds = np.asarray(after.slip) - np.asarray(before.slip)
        p, q = after.x[layout.pressure], after.x[layout.shear]
        w = pair_weights(now.problem)
        for body in BODIES:
            depth[body] += place(body, now, before, after, w, w * laws[body].depth(p, q, ds))
            sensitivities[body] += laws[body].pressure_sensitivity(p, q, ds)
        touching = p > 0
        slid = np.where(touching, np.abs(ds), 0.0)
        ratio = np.divide(np.abs(q), p, out=np.zeros(n), where=touching)
        for total, density in ((energy, np.abs(q) * slid), (energy_sensitivity, ratio * slid),
                               (work, p * slid), (work_sensitivity, slid)):  # fmt: skip
            total += place("lower", now, before, after, w, w * density)
        path[:] += np.abs(ds)

    for load in cycle:
        track, state, its = track.step(state, load, wear)
        iterations += its
        pressures.append(state.x[track.problem.layout.pressure].copy())
        shears.append(state.x[track.problem.layout.shear].copy())
        positions.append(track.positions(state))
        if track.simulation.rotates:
            measured = track.simulation.measure(track.problem, state)
            turns.append([measured[k] for k in BLOCK_ROTATION])
    block = dict(zip(BLOCK_ROTATION, np.array(turns).T, strict=True)) if turns else {}
    wear_cycle = CycleWear(
        depth, sensitivities, energy, energy_sensitivity, work, work_sensitivity, path,
        np.array(pressures), np.array(shears), state, iterations, np.array(positions), **block,
    )  # fmt: skip
    return wear_cycle, track
