"""The pivoting solver: each increment as one LCP, solved exactly by Lemke's method.

An independent algorithm for the same condensed problem as the semi-smooth Newton method
(:mod:`fretbem.solvers.complementarity` has the formulation): the tests cross-check the
two, and a user whose Newton iteration fails may choose this one instead.
"""

from __future__ import annotations

from typing import Any

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.law import ContactLaw, ContactState
from fretbem.errors import InputError
from fretbem.numerics.blas import one_blas_thread
from fretbem.validators import count_field, whole_number

from .complementarity import CondensedArrays, solve_lcp_increment
from .lemke import LemkeError
from .newton import IncrementResult, Solver, SolverConvergenceError, SolverSettingsError


class PivotingError(SolverConvergenceError):
    """Lemke's method found no solution of an increment (ray termination or pivot limit)."""


class UnsupportedLawError(InputError):
    """A contact law the pivoting solver has no LCP form for."""


def _pivots(value: Any) -> int | None:
    """None (50 x the LCP size) or a whole number >= 1 (numpy's too; True, "5", 2.5 refused)."""
    if value is None:
        return None
    fix = "give e.g. 1000, or None (50 x the LCP size)"
    return whole_number("LemkeSolver.max_pivots", value, low=1, fix=fix, error=SolverSettingsError)


@attrs.frozen
class LemkeSolver(Solver):
    """Lemke's complementary pivoting method on the LCP form of Coulomb friction.

    Exact to round-off in finitely many pivots, with no convergence parameters; reports its
    pivots as the increment's iterations.

    Attributes
    ----------
    max_pivots : int or None
        Pivots per increment before giving up (None: 50 times the LCP size).
    max_substeps : int
        Times the Simulation may halve an increment this solver failed on (default 0).
    """

    #: the LCP form keeps the blocks' force balance rows: force control only
    displacement_control = False

    max_pivots: int | None = attrs.field(default=None, converter=_pivots)
    max_substeps: int = attrs.field(
        default=0,
        converter=count_field("give e.g. 0 (the default)", low=0, error=SolverSettingsError),
    )

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
        """Solve one increment from scratch (``start`` is not needed by a pivoting method)."""
        friction = law.coulomb_form()
        if friction is None:
            raise UnsupportedLawError(
                f"the Lemke solver has the LCP form of Coulomb friction only (CoulombFriction, "
                f"or a law whose coulomb_form() gives f), but the law {type(law).__name__} "
                "gives none; use [contact] solver = 'newton' for other laws"
            )
        normal_base, tangential_base, resultant_base = problem.bases(loads)
        arrays = CondensedArrays(
            normal_map=problem.normal_map,
            tangential_map=problem.tangential_map,
            normal_base=normal_base,
            tangential_base=tangential_base,
            resultant_map=problem.resultant_map,
            resultant_base=resultant_base,
            gap=problem.gap,
        )
        try:
            with one_blas_thread():
                result = solve_lcp_increment(
                    arrays,
                    friction=friction,
                    forces=forces,
                    reference_slip=previous.slip,
                    max_pivots=self.max_pivots,
                )
        except LemkeError as failure:
            raise PivotingError(str(failure)) from failure
        return IncrementResult(result.x, result.states, result.pivots, (result.residual,))
