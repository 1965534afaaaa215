"""The cyclic load history: load steps as data, a Simulation that advances a ContactState.

``run(simulation)`` prepares (assembles and condenses once), then steps through the
history; the friction memory (slip already accumulated) is carried from step to step in
the frozen ``ContactState`` records.
"""

from __future__ import annotations

import time

import attrs
import numpy as np

from ._validators import finite
from .analytical import MindlinDeresiewicz
from .contact import SEPARATED, STATE_NAMES, CondensedContact, ContactPair
from .results import SimulationResult, StepResult
from .solver import IncrementResult, NewtonConvergenceError, Solver


class GrossSlidingError(ValueError):
    """|Q| >= f P under force control: no static equilibrium exists."""


class LoadHistoryError(ValueError):
    """A load history that cannot start or continue a contact simulation."""


@attrs.frozen
class LoadStep:
    """Loads at the end of one step, reached linearly from the previous step's.

    Attributes
    ----------
    name : str
    normal : float
        Normal load P (> 0 presses the upper body onto the lower), force per thickness.
    tangential : float
        Tangential load Q on the upper body, along the pair's tangent (+x in the scene).
    increments : int
        Equal sub-increments inside the step (friction is path dependent).
    """

    name: str
    normal: float = attrs.field(converter=float, validator=finite)
    tangential: float = attrs.field(converter=float, validator=finite)
    increments: int = attrs.field(default=1, converter=int, validator=attrs.validators.ge(1))


@attrs.frozen(eq=False)
class ContactState:
    """The pair unknowns at the end of an increment: the friction memory.

    Attributes
    ----------
    x : ndarray
        (p, q, block displacements) of the pair.
    states : ndarray of int
        SEPARATED, STICK or SLIP per pair.
    slip : ndarray
        Relative tangential displacement per pair (the stick reference of the next step).
    normal, tangential : float
        Loads reached.
    """

    x: np.ndarray
    states: np.ndarray
    slip: np.ndarray
    normal: float = 0.0
    tangential: float = 0.0
    virgin: bool = True

    @classmethod
    def initial(cls, problem: CondensedContact) -> ContactState:
        """The unloaded state: all pairs separated, no slip."""
        n = problem.n_pairs
        return cls(
            x=np.zeros(problem.normal_map.shape[1]),
            states=np.full(n, SEPARATED),
            slip=np.zeros(n),
        )


@attrs.frozen(eq=False)
class Simulation:
    """A contact pair, its load history and the solver.

    Attributes
    ----------
    pair : ContactPair
        Its upper body must carry a LoadingBlock: the history drives that block's force.
    steps : tuple of LoadStep
    solver : Solver
    reference : MindlinDeresiewicz or None
        Analytical solution to report errors against (None where theory does not apply).
    name : str
    """

    pair: ContactPair
    steps: tuple[LoadStep, ...] = attrs.field(converter=tuple)
    solver: Solver = attrs.field(factory=Solver)
    reference: MindlinDeresiewicz | None = None
    name: str = "simulation"

    def __attrs_post_init__(self) -> None:
        if self.pair.upper.loading_block is None:
            raise LoadHistoryError(
                f"the load history drives the upper body's loading block, but body "
                f"{self.pair.upper.name!r} has none; add LoadingBlock('top') to its conditions"
            )
        if not self.steps:
            raise LoadHistoryError("a simulation needs at least one load step")
        first = self.steps[0]
        if not (first.normal > 0 and first.tangential == 0):
            raise LoadHistoryError(
                f"the first load step ({first.name!r}: P = {first.normal}, Q = "
                f"{first.tangential}) must be a pure normal load, P > 0 and Q = 0, so the "
                "bodies are pressed together before any tangential load"
            )
        friction = self.pair.friction
        if friction == 0:
            raise GrossSlidingError(
                "the contact is frictionless (f = 0), so it cannot hold the upper body "
                "tangentially and under force control its tangential position is undetermined "
                "(no unique equilibrium); use a friction coefficient f > 0"
            )
        for step in self.steps:
            if step.normal <= 0:
                raise LoadHistoryError(
                    f"load step {step.name!r} has P = {step.normal}; the bodies must stay pressed "
                    "together (P > 0) under force control"
                )
            if abs(step.tangential) >= friction * step.normal:
                raise GrossSlidingError(
                    f"load step {step.name!r}: |Q| = {abs(step.tangential):g} >= f P = "
                    f"{friction * step.normal:g}, so no static equilibrium exists (gross "
                    "sliding); keep |Q| below f P under force control"
                )

    def frame(self) -> tuple[np.ndarray, np.ndarray]:
        """Mean normal and tangent of the pair: loads act along these."""
        geo = self.pair.geometry
        normal = geo["normals"].mean(axis=0)
        normal /= np.linalg.norm(normal)
        return normal, np.array([normal[1], -normal[0]])

    def forces(self, normal_load: float, tangential_load: float) -> np.ndarray:
        """Block forces for given P and Q (upper block), plus the lower block's own force."""
        n, t = self.frame()
        forces = [-normal_load * n + tangential_load * t]
        block = self.pair.lower.loading_block
        if block is not None:
            forces.append(np.asarray(block.force))
        return np.concatenate(forces)

    def prepare(self) -> CondensedContact:
        """Assemble both bodies and condense them onto the pair unknowns (cached)."""
        return self.pair.condensed()

    def _increment(self, problem, state, normal, tangential, depth=0) -> tuple:
        """Solve from ``state`` to loads (normal, tangential), halving on failure."""
        try:
            result = self.solver.solve_increment(
                problem,
                friction=self.pair.friction,
                forces=self.forces(normal, tangential),
                reference_slip=state.slip,
                start=None if state.virgin else state.x,
                start_states=None if state.virgin else state.states,
            )
        except NewtonConvergenceError as failure:
            if depth >= self.solver.max_substeps:
                raise
            mid_n = 0.5 * (state.normal + normal)
            mid_t = 0.5 * (state.tangential + tangential)
            half, it1, res1 = self._increment(problem, state, mid_n, mid_t, depth + 1)
            full, it2, res2 = self._increment(problem, half, normal, tangential, depth + 1)
            # the failed attempt's iterations were spent too: report them with the halves
            failed = list(failure.residuals)
            return full, len(failed) + it1 + it2, failed + res1 + res2
        return (
            self._advance(problem, state, result, normal, tangential),
            result.iterations,
            list(result.residuals),
        )

    @staticmethod
    def _advance(problem, state, result: IncrementResult, normal, tangential) -> ContactState:
        slip = problem.tangential_base + problem.tangential_map @ result.x
        return ContactState(result.x, result.states, slip, normal, tangential, virgin=False)

    def step(self, problem: CondensedContact, state: ContactState, load: LoadStep):
        """Advance ``state`` through one load step; returns (new state, iterations, residuals)."""
        iterations, residuals = 0, []
        start_n, start_t = state.normal, state.tangential
        for k in range(1, load.increments + 1):
            frac = k / load.increments
            target_n = start_n + frac * (load.normal - start_n)
            target_t = start_t + frac * (load.tangential - start_t)
            state, its, res = self._increment(problem, state, target_n, target_t)
            iterations += its
            residuals += res
        return state, iterations, residuals


def run(simulation: Simulation) -> SimulationResult:
    """Prepare once and step through the whole history; returns per-step results."""
    start = time.perf_counter()
    problem = simulation.prepare()
    pair = simulation.pair
    timings = {
        "assembly": sum(b.timings.get("assembly", 0.0) for b in (pair.upper, pair.lower)),
        "factorisation": sum(b.timings.get("factorisation", 0.0) for b in (pair.upper, pair.lower)),
        "condensation": problem.seconds,
    }
    state = ContactState.initial(problem)
    history: list[float] = []
    steps = []
    for load in simulation.steps:
        tic = time.perf_counter()
        state, iterations, residuals = simulation.step(problem, state, load)
        seconds = time.perf_counter() - tic
        history.append(load.tangential)
        steps.append(
            StepResult.build(
                simulation, problem, load, state, iterations, residuals, seconds, tuple(history)
            )
        )
    timings["steps"] = sum(s.seconds for s in steps)
    timings["total"] = time.perf_counter() - start
    return SimulationResult(simulation=simulation, steps=tuple(steps), timings=timings)


__all__ = ["STATE_NAMES", "ContactState", "LoadStep", "Simulation", "run"]
