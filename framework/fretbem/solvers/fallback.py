"""A solver that falls back to a second algorithm on the increments the first fails on."""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.law import ContactLaw, ContactState
from fretbem.errors import SolverSettingsError
from fretbem.validators import count_field

from .newton import IncrementResult, SemiSmoothNewton, Solver, SolverConvergenceError
from .pivoting import LemkeSolver


@attrs.frozen
class FallbackSolver(Solver):
    """Try ``primary``; where it fails on an increment, solve that increment by ``fallback``.

    The default, Newton then Lemke, keeps Newton's speed and uses the pivoting method only
    on the increments Newton cannot converge on (it cycled on the half-plane pair with a
    small datum, for instance). The reported iterations add both attempts'.

    Attributes
    ----------
    primary, fallback : Solver
    max_substeps : int
        Times the Simulation may halve an increment both failed on (default 0).
    """

    primary: Solver = attrs.field(
        factory=lambda: SemiSmoothNewton(max_substeps=0),
        validator=attrs.validators.instance_of(Solver),
    )
    fallback: Solver = attrs.field(
        factory=LemkeSolver, validator=attrs.validators.instance_of(Solver)
    )
    max_substeps: int = attrs.field(
        default=0,
        converter=count_field("give e.g. 0 (the default)", low=0, error=SolverSettingsError),
    )

    @property
    def displacement_control(self) -> bool:
        """Whether both solvers take steps driven by displacement (and a rotating block)."""
        return all(getattr(s, "displacement_control", True) for s in (self.primary, self.fallback))

    def solve_increment(
        self,
        problem: CondensedContact,
        law: ContactLaw,
        *,
        forces: np.ndarray,
        loads: np.ndarray,
        previous: ContactState,
        start: ContactState | None,
    ) -> IncrementResult:
        """The primary's answer, or the fallback's where the primary raises a convergence
        error (a fallback failure is raised with the primary's residuals attached)."""
        arguments = {"forces": forces, "loads": loads, "previous": previous, "start": start}
        try:
            return self.primary.solve_increment(problem, law, **arguments)
        except SolverConvergenceError as failure:
            spent = list(failure.residuals)
        try:
            result = self.fallback.solve_increment(problem, law, **arguments)
        except SolverConvergenceError as failure:
            failure.residuals = spent + list(failure.residuals)
            raise
        return IncrementResult(
            result.x,
            result.states,
            len(spent) + result.iterations,
            (*spent, *result.residuals),
        )


def with_fallback(simulation):
    """``simulation`` with its Newton solver wrapped in a fallback to Lemke's method, or None
    when its solver is not the plain Newton solver (an explicit choice is kept).

    The run pipeline uses it to retry a run whose Newton iteration failed (bulk stress
    already in the first step, for instance) instead of reporting the failure. A simulation
    whose pad block rotates, or with a step driven by displacement (delta or approach), gets
    None too: Lemke's LCP form keeps the force balance of a non-rotating, force-driven block
    (the Simulation refuses the Lemke solver for those).
    """
    solver = getattr(simulation, "solver", None)
    driven = any(not step.controls.by_force for step in getattr(simulation, "steps", ()))
    if type(solver) is not SemiSmoothNewton or getattr(simulation, "rotates", False) or driven:
        return None
    fallback = FallbackSolver(
        primary=attrs.evolve(solver, max_substeps=0),
        fallback=LemkeSolver(),
        max_substeps=solver.max_substeps,
    )
    return attrs.evolve(simulation, solver=fallback)
