"""The cyclic load history: load steps as data, a Simulation that advances a ContactState.

``run(simulation)`` prepares (assembles and condenses once), then steps through the
history; the law's memory (slip already accumulated) is carried from step to step in the
frozen :class:`~fretbem.contact.law.ContactState` records.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import math
import numbers
import time
from collections.abc import Iterator, Mapping

import attrs
import numpy as np

from fretbem.bem.resources import check_resources, run_size
from fretbem.contact import control
from fretbem.contact import rotation as pad_rotation
from fretbem.contact.condensation import CondensedContact
from fretbem.contact.control import Controls
from fretbem.contact.law import (
    STATE_NAMES,
    ContactLaw,
    ContactState,
    GrossSlidingError,
    PairState,
)
from fretbem.contact.pairs import ContactPair
from fretbem.contact.rotation import RotationError
from fretbem.errors import InputError, ResultCheckError
from fretbem.numerics.memory import KEPT_MEMORY_DOFS, kept_memory
from fretbem.solvers.newton import IncrementResult, SemiSmoothNewton, Solver, SolverConvergenceError
from fretbem.solvers.step_memo import Reached, StepMemo
from fretbem.solvers.warm_start import WarmStart
from fretbem.verification.checks import check_step, pair_positions, step_names
from fretbem.verification.closed_forms import MindlinDeresiewicz

from .results import IncrementRecord, SimulationResult, StepResult, pair_x
from .validators import as_scalar, count_field, flag, number_field, real_number


class LoadHistoryError(InputError):
    """A load history that cannot start or continue a contact simulation."""


def _load_amplitudes(value) -> dict[str, float]:
    """Each named load's amplitude: a number (no True, no "3"), finite."""
    if type(value) is dict and not value:  # no named load (the usual step), no ABC lookup
        return {}
    if not isinstance(value, Mapping):
        raise InputError(
            f"LoadStep.loads must be a mapping of load name to amplitude, got {value!r}; give "
            'e.g. {"bulk": 150.0}, or {} for no named load'
        )
    out = {}
    for name, amplitude in value.items():
        amplitude = as_scalar(amplitude)
        where = f"LoadStep.loads[{name!r}]"
        if isinstance(amplitude, (bool, np.bool_)) or not isinstance(amplitude, numbers.Real):
            shown = f'the string "{amplitude}"' if isinstance(amplitude, str) else repr(amplitude)
            raise InputError(
                f"{where} must be a number, got {shown} (the amplitude of the named load); "
                "give the amplitude (e.g. the bulk stress in MPa), or leave the load out for 0"
            )
        out[str(name)] = float(amplitude)
    return out


def _finite_loads(instance, attribute, value) -> None:
    bad = {name: a for name, a in value.items() if not math.isfinite(a)}
    if bad:
        raise InputError(
            f"LoadStep.loads must be finite numbers, got {bad!r}; give each amplitude as a "
            "finite number, or leave the load out for 0"
        )


#: what the rotation drives of a step are and what to give instead of a bad one
ROTATION_DRIVES = {
    "moment": ("N mm/mm, the moment on the pad's block", "the moment in N mm/mm"),
    "rotation": ("rad, the actuator's rotation", "the rotation in rad"),
}


def _rotation_drive(value, field) -> float | None:
    """A step's moment or rotation: None, or a finite number (no True, no "1.0")."""
    if value is None:
        return None
    what, give = ROTATION_DRIVES[field.name]
    fix = f"give {give}, or None to leave the block's rotation as the rig holds it"
    return real_number(f"LoadStep.{field.name}", value, what=what, fix=fix, error=InputError)


def _point(value) -> np.ndarray | None:
    """A pivot: None, or a finite point (x, y) in the pad's axes (mm)."""
    if value is None:
        return None
    fix = "give two numbers (x, y), or None to find it above the pad's first contact"
    if isinstance(value, (str, bytes, Mapping)) or np.ndim(value) != 1 or len(value) != 2:
        raise LoadHistoryError(
            f"Simulation.pivot must be a point (x, y) in the pad's axes (mm), got {value!r}; {fix}"
        )
    where = "Simulation.pivot"
    return np.array([real_number(where, v, what="mm", fix=fix, error=LoadHistoryError)
                     for v in value])  # fmt: skip


@attrs.frozen
class LoadStep:
    """Loads (or block displacements) at the end of one step, reached linearly from the
    previous step's.

    Each direction of the pad's loading block is driven by force or by displacement: give
    ``normal`` (P) or ``approach``, and ``tangential`` (Q) or ``delta``
    (:mod:`fretbem.contact.control`; the displacements are the pad's block against the
    specimen's held end).

    Attributes
    ----------
    name : str
    normal : float or None
        Normal load P (> 0 presses the upper body onto the lower), force per thickness;
        None when ``approach`` drives the step.
    tangential : float
        Tangential load Q on the upper body, along the pair's tangent (+x in the scene);
        leave it 0 when ``delta`` drives the step.
    increments : int
        Equal sub-increments inside the step (friction is path dependent).
    loads : mapping of str to float
        Amplitudes of named body loads (e.g. ``{"bulk": sigma_B}`` for a
        ``Traction(..., load="bulk")``); a load not given is 0.
    delta : float or None
        Tangential displacement of the pad's block (mm, along the tangent) imposed instead
        of Q: displacement control.
    approach : float or None
        Normal approach of the pad's block (mm, > 0 presses) imposed instead of P.
    cycle : int
        The load cycle this step belongs to (1, 2, ...; 0: none), for the per-cycle results
        of a cyclic history (:mod:`fretbem.fretting`).
    moment : float or None
        Moment M (N mm/mm, counterclockwise) the pad's block applies to the pad about the
        rig's pivot (:mod:`fretbem.contact.rotation`): the block's rotation is then free.
    rotation : float or None
        The actuator's rotation theta_a (rad, counterclockwise) instead: the block turns
        by theta_a - M / k_r through the rig's rotational spring (rigid by default). Neither
        given: theta_a = 0, the block held as the rig holds it.
    """

    name: str
    normal: float | None = attrs.field(
        converter=number_field(
            "the normal load P, N/mm", "give P in N/mm, or None when approach drives the step",
            none=True,
        )
    )  # fmt: skip
    tangential: float = attrs.field(
        default=0.0,
        converter=number_field(
            "the tangential load Q, N/mm", "give Q in N/mm, or 0 when delta drives the step"
        ),
    )
    increments: int = attrs.field(
        default=1, converter=count_field("give the number of equal sub-increments (1: none)")
    )
    loads: Mapping[str, float] = attrs.field(
        factory=dict, converter=_load_amplitudes, validator=_finite_loads, hash=False
    )
    delta: float | None = attrs.field(
        default=None,
        converter=number_field(
            "the pad block's tangential displacement, mm",
            "give delta in mm, or None when Q drives the step",
            none=True,
        ),
        kw_only=True,
    )
    approach: float | None = attrs.field(
        default=None,
        converter=number_field(
            "the pad block's normal approach, mm",
            "give the approach in mm, or None when P drives the step",
            none=True,
        ),
        kw_only=True,
    )
    cycle: int = attrs.field(
        default=0,
        converter=count_field("give the load cycle of the step (1, 2, ...; 0: none)", low=0),
        kw_only=True,
    )
    moment: float | None = attrs.field(
        default=None, converter=attrs.Converter(_rotation_drive, takes_field=True), kw_only=True
    )
    rotation: float | None = attrs.field(
        default=None, converter=attrs.Converter(_rotation_drive, takes_field=True), kw_only=True
    )

    def __attrs_post_init__(self) -> None:
        if (self.normal is None) == (self.approach is None):
            raise LoadHistoryError(
                f"load step {self.name!r} must give the normal load P (normal=) or the normal "
                f"approach (approach=), exactly one of them; got normal={self.normal}, "
                f"approach={self.approach}"
            )
        if self.delta is not None and self.tangential != 0.0:
            raise LoadHistoryError(
                f"load step {self.name!r} gives both Q = {self.tangential} and delta = "
                f"{self.delta}; a tangential direction is driven by force or by displacement: "
                "keep one of them"
            )
        if self.moment is not None and self.rotation is not None:
            raise LoadHistoryError(
                f"load step {self.name!r} gives both the moment M = {self.moment} and the "
                f"rotation theta = {self.rotation}; the pad block's rotation is driven by its "
                "moment or by the actuator's rotation: keep one of them"
            )

    @property
    def controls(self) -> Controls:
        """Which directions this step drives by displacement (and the rotation by moment)."""
        return _controls(
            "force" if self.approach is None else "displacement",
            "force" if self.delta is None else "displacement",
            "rotation" if self.moment is None else "moment",
        )

    @property
    def rotation_target(self) -> float:
        """M or the actuator's rotation (0 when the step gives neither)."""
        if self.moment is not None:
            return self.moment
        return 0.0 if self.rotation is None else self.rotation

    @property
    def turns(self) -> bool:
        """Whether the step moves the pad block's rotation (a moment or a rotation != 0)."""
        return self.moment is not None or bool(self.rotation)

    @property
    def normal_target(self) -> float:
        """P or the approach, whichever drives the step."""
        return self.normal if self.approach is None else self.approach

    @property
    def tangential_target(self) -> float:
        """Q or delta, whichever drives the step."""
        return self.tangential if self.delta is None else self.delta


@attrs.frozen(eq=False)
class Simulation:
    """A contact pair, its load history, the contact law and the solver.

    Attributes
    ----------
    pair : ContactPair
        Its upper body must carry a LoadingBlock: the history drives that block's force.
    steps : tuple of LoadStep
    solver : Solver
        Default :class:`~fretbem.solvers.newton.SemiSmoothNewton`.
    law : ContactLaw
        E.g. :class:`~fretbem.contact.law.CoulombFriction` (keyword, required).
    reference : MindlinDeresiewicz or None
        Analytical solution to report errors against (None where theory does not apply).
    name : str
    rig : Rig
        Springs between the actuator and the pad's block (default rigid): a step's delta
        or approach is then the actuator's (:mod:`fretbem.contact.control`).
    pivot : ndarray, shape (2,) or None
        Where a rotating block turns, in the pad's own axes (mm); None: found from the pair
        (:func:`fretbem.contact.rotation.pivot`). Runs that change the pair as they go
        (finite sliding, wear) pin it where the pad started (:meth:`pinned`).
    """

    pair: ContactPair
    steps: tuple[LoadStep, ...] = attrs.field(converter=tuple)
    solver: Solver = attrs.field(
        factory=SemiSmoothNewton, validator=attrs.validators.instance_of(Solver)
    )
    law: ContactLaw = attrs.field(kw_only=True, validator=attrs.validators.instance_of(ContactLaw))
    reference: MindlinDeresiewicz | None = None
    name: str = "simulation"
    rig: control.Rig = attrs.field(
        factory=control.Rig, validator=attrs.validators.instance_of(control.Rig), kw_only=True
    )
    pivot: np.ndarray | None = attrs.field(default=None, kw_only=True, converter=_point)
    #: the controlled problems of the condensed pair, per Controls (a private cache)
    _controlled: dict = attrs.field(init=False, factory=dict, repr=False)
    #: the rotating problem of each condensed pair (a private cache)
    _rotating: dict = attrs.field(init=False, factory=dict, repr=False)
    #: :attr:`rotates`, found once (a run asks it at every increment)
    _rotates: bool = attrs.field(init=False, default=False, repr=False)

    def __attrs_post_init__(self) -> None:
        object.__setattr__(
            self, "_rotates",
            math.isfinite(self.rig.rotational) or any(s.turns for s in self.steps),
        )  # fmt: skip
        if self.pair.upper.loading_block is None:
            raise LoadHistoryError(
                f"the load history drives the upper body's loading block, but body "
                f"{self.pair.upper.name!r} has none; add LoadingBlock('top') to its conditions"
            )
        if not self.steps:
            raise LoadHistoryError("a simulation needs at least one load step")

        step_names([step.name for step in self.steps])
        first = self.steps[0]
        if not (first.normal_target > 0 and first.tangential_target == 0):
            what = "P" if first.approach is None else "approach"
            raise LoadHistoryError(
                f"the first load step ({first.name!r}: {what} = {first.normal_target}, "
                f"{'Q' if first.delta is None else 'delta'} = {first.tangential_target}) must "
                f"be a pure normal load, {what} > 0 and {'Q' if first.delta is None else 'delta'}"
                " = 0, so the bodies are pressed together before any tangential load"
            )
        for step in self.steps:
            if step.normal is not None and step.normal <= 0:
                raise LoadHistoryError(
                    f"load step {step.name!r} has P = {step.normal}; the bodies must stay pressed "
                    "together (P > 0) under force control"
                )
        driven = [s.name for s in self.steps if not s.controls.by_force]
        if self.rotates and not getattr(self.solver, "displacement_control", True):
            raise LoadHistoryError(
                f"the pad block rotates (a rotational rig stiffness, or a step's moment or "
                f"rotation), which the {type(self.solver).__name__} solver does not take (its "
                "LCP form keeps the force balance of a non-rotating block); use the Newton "
                "solver ([contact] solver = 'newton')"
            )
        if driven and not getattr(self.solver, "displacement_control", True):
            raise LoadHistoryError(
                f"load steps {driven} impose the block's displacement (delta or approach), "
                f"which the {type(self.solver).__name__} solver does not take (its LCP form "
                "keeps the force balance); use the Newton solver ([contact] solver = "
                "'newton') or drive those steps by force"
            )
        known = set(self.pair.upper.load_names) | set(self.pair.lower.load_names)
        for step in self.steps:
            unknown = sorted(set(step.loads) - known)
            if unknown:
                raise LoadHistoryError(
                    f"load step {step.name!r} drives loads {unknown} that no body responds to "
                    f"(the bodies' loads are {sorted(known)}); name them in a "
                    "Traction(..., load=name) condition or remove them from the step"
                )
        self.law.check_history(self.steps)

    @property
    def rotates(self) -> bool:
        """Whether the pad block's rotation is an unknown: a rotational rig spring, or a
        step that gives a moment or a rotation. Otherwise the block does not rotate and the
        problem is exactly that of a non-rotating block."""
        return self._rotates

    def frame(self, side: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Mean normal and tangent of the pair: loads act along these; in the axes of the
        body on ``side`` (its block's: they differ for a pad turned along an arc) or of the
        pair frame (None)."""
        return self.pair.pairing().load_frame(side)

    def forces(self, normal_load: float, tangential_load: float) -> np.ndarray:
        """Block forces for given P and Q (upper block, in its axes), plus the lower
        block's own force."""
        n, t = self.frame("upper")
        forces = [-normal_load * n + tangential_load * t]
        block = self.pair.lower.loading_block
        if block is not None:
            forces.append(np.asarray(block.force))
        return np.concatenate(forces)

    def prepare(self) -> CondensedContact:
        """Assemble both bodies and condense them onto the pair unknowns (cached); with the
        pad block's rotation among them when the simulation :attr:`rotates`."""
        return self.condense(self.pair)

    def condense(self, pair: ContactPair) -> CondensedContact:
        """``pair`` (this simulation's, or a re-paired or worn one) condensed, with the pad
        block's rotation about :meth:`block_pivot` when the simulation :attr:`rotates`."""
        problem = pair.condensed()
        return self.rotating(problem) if self.rotates else problem

    def block_pivot(self) -> np.ndarray:
        """Where the pad's block turns, in the pad's axes: :attr:`pivot`, or the rig's pivot
        above the first contact of the simulation's own pair."""
        if self.pivot is not None:
            return self.pivot
        try:
            return pad_rotation.pivot(self.pair.condensed(), self.rig.pivot_height)
        except RotationError as err:
            raise LoadHistoryError(str(err)) from None

    def pinned(self) -> Simulation:
        """The simulation with a rotating block's pivot fixed where it is now, for a run
        that changes the pair (a worn or re-paired problem keeps the first's pivot)."""
        if not self.rotates or self.pivot is not None:
            return self
        return attrs.evolve(self, pivot=self.block_pivot())

    def rotating(self, problem: CondensedContact) -> CondensedContact:
        """``problem`` with the pad block's rotation held by the rig (cached per problem)."""
        cached = self._rotating.get(id(problem))
        if cached is None or cached[0] is not problem:
            pivot = self.block_pivot()
            try:
                turned = control.rotating(problem, self.rig, pivot)
            except RotationError as err:
                raise LoadHistoryError(str(err)) from None
            cached = (problem, turned)
            self._rotating.clear()
            self._rotating[id(problem)] = cached
        return cached[1]

    def controlled(self, problem: CondensedContact, controls: Controls) -> CondensedContact:
        """``problem`` with the pad block's equations of ``controls`` (cached per control)."""
        if controls.by_force:
            return problem
        cache = self._controlled.get(id(problem))
        if cache is None or cache[0] is not problem:
            cache = (problem, {})
            self._controlled.clear()
            self._controlled[id(problem)] = cache
        if controls not in cache[1]:
            cache[1][controls] = control.controlled(problem, controls, self.rig)
        return cache[1][controls]

    def measure(self, problem: CondensedContact, state: ContactState) -> dict:
        """P, Q, the approach and delta of ``state`` (the pad block against the datum)."""
        return control.measure(problem, state.x, problem.amplitudes(state.loads), self.rig)

    def _start(self, problem, state: ContactState, controls: Controls) -> tuple:
        """The values of the step's driven quantities at ``state`` (where the step starts):
        P or the approach, Q or delta, and the actuator's rotation or M."""
        turning = _turning(problem)
        if controls.by_force and not turning:
            return state.normal, state.tangential, 0.0
        measured = self.measure(problem, state)
        normal = state.normal if controls.normal == "force" else measured["approach"]
        tangential = state.tangential if controls.tangential == "force" else measured["delta"]
        rotation = 0.0
        if turning:
            rotation = measured["moment" if controls.rotation == "moment" else "rotation"]
        return normal, tangential, rotation

    def _increment(
        self, problem, state, normal, tangential, loads, depth=0, controls=None, rotation=0.0,
        guess=None,
    ):  # fmt: skip
        """Solve from ``state`` to the driven values (normal, tangential, rotation) and named
        loads, halving on failure; ``controls`` says which values are forces or
        displacements (and whether ``rotation`` is the actuator's rotation or M). ``guess``
        (a ContactState, optional) is tried as the Newton start first (a warm start:
        :mod:`fretbem.solvers.warm_start`); if it fails the usual start is taken."""
        controls = Controls() if controls is None else controls
        driven = self.controlled(problem, controls)
        forces = self.forces(
            normal if controls.normal == "force" else 0.0,
            tangential if controls.tangential == "force" else 0.0,
        )
        if _turning(problem):
            forces = np.append(forces, 0.0)
        targets = control.targets(problem, controls, normal, tangential, forces, rotation)
        beta = problem.amplitudes(loads)
        spent: list[float] = []  # residuals of a failed warm start, reported with the rest
        try:
            result = None
            if guess is not None:
                try:
                    result = self.solver.solve_increment(
                        driven, self.law, forces=targets, loads=beta, previous=state, start=guess
                    )
                except SolverConvergenceError as failure:
                    spent = list(failure.residuals)
            if result is None:
                result = self.solver.solve_increment(
                    driven, self.law, forces=targets, loads=beta, previous=state,
                    start=None if state.virgin else state,
                )  # fmt: skip
        except SolverConvergenceError as failure:
            if spent:
                failure.residuals = spent + list(failure.residuals)
            if depth >= self.solver.max_substeps:
                raise
            start_n, start_t, start_r = self._start(problem, state, controls)
            mid_n = 0.5 * (start_n + normal)
            mid_t = 0.5 * (start_t + tangential)
            mid_r = 0.5 * (start_r + rotation)
            mid_loads = loads_between(state.loads, loads, 0.5)
            half, it1, res1 = self._increment(
                problem, state, mid_n, mid_t, mid_loads, depth + 1, controls, mid_r
            )
            full, it2, res2 = self._increment(
                problem, half, normal, tangential, loads, depth + 1, controls, rotation
            )
            # the failed attempt's iterations were spent too: report them with the halves
            failed = list(failure.residuals)
            return full, len(failed) + it1 + it2, failed + res1 + res2
        return (
            self._advance(problem, result, normal, tangential, loads, controls),
            len(spent) + result.iterations,
            spent + list(result.residuals),
        )

    def _advance(self, problem, result: IncrementResult, normal, tangential, loads, controls=None):
        """The state ``result`` reached. Its unknowns, states and slip are the solver's own
        arrays, which nothing writes again: frozen here (not copied), the increment and step
        records take them, and their slices, as they are."""
        beta = problem.amplitudes(loads)
        slip = problem.relative_tangential(result.x, beta)
        if controls is not None and not controls.by_force:
            measured = control.measure(problem, result.x, beta, self.rig)
            if controls.normal != "force":
                normal = measured["normal"]
            if controls.tangential != "force":
                tangential = measured["tangential"]
        x, states = result.x, result.states
        for values in (x, states, slip):
            values.setflags(write=False)
        return ContactState(x, states, slip, normal, tangential, dict(loads), virgin=False)

    def step(
        self, problem: CondensedContact, state: ContactState, load: LoadStep, record=None,
        starts=None,
    ):  # fmt: skip
        """Advance ``state`` through one load step; returns (new state, iterations, residuals).

        ``record(state)``, if given, is called after every increment (the per-increment
        results of a cyclic history). ``starts`` (a warm start's mapper,
        :meth:`fretbem.solvers.warm_start.WarmStart.mapper`) gives each increment's first
        Newton start. A rotating block's increments are each checked by :func:`check_tilt`
        (a contact rolled onto the zone's end is refused with the tipping block's message)."""
        iterations, residuals = 0, []
        controls = load.controls
        turning = self.rotates
        start_n, start_t, start_r = self._start(problem, state, controls)
        start_loads = dict(state.loads)
        for k in range(1, load.increments + 1):
            frac = k / load.increments
            target_n = start_n + frac * (load.normal_target - start_n)
            target_t = start_t + frac * (load.tangential_target - start_t)
            target_r = start_r + frac * (load.rotation_target - start_r)
            target_loads = loads_between(start_loads, load.loads, frac)
            guess = None
            if starts is not None:
                guess = starts.start(load.name, k, load.increments, state)
            state, its, res = self._increment(
                problem, state, target_n, target_t, target_loads, controls=controls,
                rotation=target_r, guess=guess,
            )  # fmt: skip
            if turning:
                check_tilt(self, problem, state, load)
            iterations += its
            residuals += res
            if record is not None:
                record(state)
        return state, iterations, residuals


@functools.cache
def _controls(normal: str, tangential: str, rotation: str) -> Controls:
    """The (frozen) Controls of these three choices, made once: every increment of a step
    asks its step for them."""
    return Controls(normal=normal, tangential=tangential, rotation=rotation)


def _turning(problem: CondensedContact) -> bool:
    """Whether ``problem`` carries the pad block's rotation among its unknowns."""
    return problem.rotation is not None and problem.rotation.in_unknowns


def check_balance(simulation: Simulation, problem) -> None:
    """Refuse, before solving, a step whose P, Q and M put the contact's centre d = (h Q -
    M) / P beyond the candidate zone (by half its reach again: no contact there can carry
    it); the solver would otherwise overflow on it."""
    height, reach = pad_rotation.lever(problem)
    for load in simulation.steps:
        if load.controls != Controls(rotation="moment") or not load.normal > 0:
            continue
        centre = (height * load.tangential - load.moment) / load.normal
        if not reach[0] * 1.5 <= centre <= reach[1] * 1.5:
            raise LoadHistoryError(no_balance(simulation, problem, load, "found before solving"))


class BlockTippingError(SolverConvergenceError, ResultCheckError):
    """A rotating block's increment refused by :func:`check_tilt`; its message is already
    the tipping block's (:func:`no_balance`). It is the zone-edge check applied at every
    increment, so it is a failed result check too (``fretbem run`` exits 1, as the check
    at a step's end does)."""

    check = "zone_edge"


def no_balance(simulation: Simulation, problem, load: LoadStep, failure) -> str:
    """The message of a rotating simulation whose step found no solution (the likely cause,
    the block tipping, with the scene keys that turn it)."""
    keys = [name for name, given in (
        ("[load] moment", any(s.moment is not None for s in simulation.steps)),
        ("[load.cycle] M_amplitude", any(s.moment is not None and s.cycle for s in
                                         simulation.steps)),
        ("[load] rotation", any(s.rotation is not None for s in simulation.steps)),
        ("[rig] stiffness_rotation", math.isfinite(simulation.rig.rotational)),
    ) if given]  # fmt: skip
    by_moment = load.controls == Controls(rotation="moment")  # P, Q and M given
    return pad_rotation.no_balance(
        problem, load.name, str(failure).split(";")[0],
        normal=load.normal if by_moment else None,
        tangential=load.tangential if by_moment else None,
        moment=load.moment if by_moment else None, keys=keys,
    )  # fmt: skip


def check_tilt(simulation: Simulation, problem, state: ContactState, load) -> None:
    """Refuse an increment of a rotating block whose contact reached an end of the candidate
    zone (or whose tilt is not a number), with the tipping block's message, before the next
    carried friction history, or a sliding run's next re-pairing, builds on its nonsense.

    The moment about the pivot is carried by the pressure's resultant, whose centre lies
    where the pressure does; a non-negative pressure over the zone carries at most P times
    the zone's reach. An answer with the zone's outermost pair in contact is at that limit:
    the block's rotation rolled the contact onto the zone's end, and the true contact lies
    beyond it (the block tips, or rolls further than the zone reaches), so the increment's
    tractions are those of a truncated contact, whatever its tilt. Checked at every
    increment of every stepping loop (:meth:`Simulation.step`, finite sliding and sliding
    wear; a step's end alone is checked for every block by the zone-edge check): the
    friction history carried to the next increments would inherit the truncation."""
    if not simulation.rotates:
        return
    tilt = float(state.x[problem.layout.rotation("upper")])
    reason = None if math.isfinite(tilt) else f"the block's tilt reached {tilt} rad"
    if reason is None:
        along = pad_rotation.in_pad_axes(problem.pair, problem.pairing.points)[:, 0]
        ends = np.unique(np.argsort(along)[[0, -1]])
        touching = ends[state.states[ends] != PairState.SEPARATED]
        if touching.size:
            where = " and ".join(f"x = {along[k]:.4g} mm" for k in touching)
            reason = (
                f"the contact reached the zone's end at {where} in the pad's axes with the "
                f"block's tilt at {tilt:.3g} rad: the moment needs the pressure's centre at or "
                "beyond the zone's end"
            )
    if reason is not None:
        raise BlockTippingError(no_balance(simulation, problem, load, reason))


def loads_between(start: Mapping[str, float], end: Mapping[str, float], frac: float) -> dict:
    """Named load amplitudes a fraction ``frac`` of the way from ``start`` to ``end``: a
    load only one of them names is 0 in the other (a load a step drops ramps down to 0 over
    its increments; one it adds ramps up). Every stepping loop uses this rule."""
    names = dict.fromkeys([*start, *end])
    return {
        name: start.get(name, 0.0) + frac * (end.get(name, 0.0) - start.get(name, 0.0))
        for name in names
    }


def run(
    simulation: Simulation,
    *,
    progress=None,
    check: bool = True,
    memo: StepMemo | None = None,
    warm: WarmStart | None = None,
) -> SimulationResult:
    """Prepare once and step through the whole history; returns per-step results.

    Every step's result passes the result checks (:func:`fretbem.verification.checks.check_step`:
    equilibrium, the candidate zone's edge, something holding the pad tangentially) before
    the next step starts; a failure raises its named ResultCheckError (``check=False``
    skips them, to inspect a failed run). ``progress(k, n, step)`` is called after each step.
    ``memo`` (a :class:`~fretbem.solvers.step_memo.StepMemo`) supplies the first steps when
    an earlier history on the same problem solved the same ones, and keeps those solved here.
    ``warm`` (a :class:`~fretbem.solvers.warm_start.WarmStart`: a run of the same history on
    another mesh of the contact faces) starts each increment's Newton iteration on that
    run's pattern; the unknowns are the same to the solver's tolerance, in fewer iterations.
    The run is checked against the machine's memory and, from
    :data:`~fretbem.numerics.memory.KEPT_MEMORY_DOFS` boundary DOFs on, keeps its large
    arrays' memory for the next ones until it ends (:func:`run_resources`).
    """

    start = time.perf_counter()
    check = flag("run check", check)
    with run_resources(simulation):
        return _run(simulation, start, progress, check, memo, warm)


#: boundary DOFs the enclosing :func:`run_resources` block checked (0 outside any)
_CHECKED = contextvars.ContextVar("fretbem checked run DOFs", default=0)


@contextlib.contextmanager
def run_resources(simulation: Simulation) -> Iterator[None]:
    """The block every run path solves in (:func:`run`, finite sliding, wear, a sweep's
    batch, the run pipeline): the simulation's boundary DOFs checked against the machine's
    memory (:func:`~fretbem.bem.resources.check_resources`), and from
    :data:`~fretbem.numerics.memory.KEPT_MEMORY_DOFS` on its large arrays' memory kept for
    the next ones until the block ends (:func:`~fretbem.numerics.memory.kept_memory`). A
    block inside one that checked at least as many DOFs is not checked again: the outer
    estimate is of the whole run, and the memory it holds is no longer available."""
    size = run_size(simulation.pair)
    dofs, checked = size["dofs"], _CHECKED.get()
    if dofs > checked:
        check_resources(**size)
    token = _CHECKED.set(max(dofs, checked))
    try:
        with kept_memory(dofs >= KEPT_MEMORY_DOFS):
            yield
    finally:
        _CHECKED.reset(token)


def _run(simulation, start, progress, check, memo, warm) -> SimulationResult:
    """:func:`run` after the resource check."""
    pair = simulation.pair
    problem = simulation.prepare()
    timings = {
        "assembly": sum(b.timings.get("assembly", 0.0) for b in (pair.upper, pair.lower)),
        "factorisation": sum(b.timings.get("factorisation", 0.0) for b in (pair.upper, pair.lower)),
        "condensation": problem.seconds,
    }
    if simulation.rotates:
        check_balance(simulation, problem)
    friction = getattr(simulation.law, "friction", float("nan"))
    along = pair_x(problem)  # the pairs' positions and what the checks read of them, once
    positions = pair_positions(along) if check else None
    checks = (lambda step: check_step(step, friction, positions=positions)) if check else None
    state = ContactState.initial(problem)
    history: list[float] = []
    steps = []
    cursor = None if memo is None else memo.cursor(problem, simulation)
    starts = None if warm is None else warm.mapper(problem)
    for k, load in enumerate(simulation.steps, start=1):
        tic = time.perf_counter()
        reached = None if cursor is None else cursor.find(load)
        if reached is None:
            increments: list[IncrementRecord] = []

            def record(end: ContactState, kept=increments) -> None:
                kept.append(IncrementRecord.of(problem, end, simulation.rig))

            try:
                state, iterations, residuals = simulation.step(problem, state, load, record, starts)
            except SolverConvergenceError as failure:
                if not simulation.rotates or isinstance(failure, BlockTippingError):
                    raise
                message = no_balance(simulation, problem, load, failure)
                raise SolverConvergenceError(message, failure.residuals) from None
            if cursor is not None:
                cursor.keep(load, Reached(state, iterations, tuple(residuals), tuple(increments)))
        else:
            state, iterations = reached.state, reached.iterations
            residuals, increments = list(reached.residuals), list(reached.increments)
        seconds = time.perf_counter() - tic
        history.append(load.tangential if load.delta is None else state.tangential)
        step = StepResult.build(
            simulation, problem, load, state, iterations, residuals, seconds, tuple(history),
            last=increments[-1], increments=tuple(increments), checks=checks, x=along,
        )  # fmt: skip
        steps.append(step)
        if progress is not None:
            progress(k, len(simulation.steps), step)
    timings["steps"] = sum(s.seconds for s in steps)
    timings["total"] = time.perf_counter() - start
    return SimulationResult(simulation=simulation, steps=tuple(steps), timings=timings)


__all__ = [
    "STATE_NAMES",
    "BlockTippingError",
    "ContactState",
    "GrossSlidingError",
    "LoadHistoryError",
    "LoadStep",
    "Simulation",
    "check_balance",
    "check_tilt",
    "loads_between",
    "no_balance",
    "run",
    "run_resources",
]
