"""The contact law as an object: Coulomb friction in Alart-Curnier form, and its state.

A law turns the pair tractions (p, q), the deformed gap g and the tangential slip
increment s into complementarity functions F_n, F_t whose roots are the contact
conditions, and gives their generalised Jacobian rows (the semi-smooth Newton method
needs both). Coulomb friction (Alart and Curnier 1991)::

    F_n = p - max(0, p - r_n g),   F_t = q - proj[-f p^, f p^](q + r_t s),   p^ = max(0, p - r_n g)

Its memory (the slip reached, the reference of the next increment's stick) lives in the
frozen :class:`ContactState`, which has room for more state (``memory``, e.g. a wear depth).
docs/how-to/new-contact-law.rst shows how to add a law.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from enum import IntEnum
from typing import Any

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.validators import number_field


class PairState(IntEnum):
    """Contact state of a node pair."""

    SEPARATED = 0
    STICK = 1
    SLIP = 2


#: state names, indexed by PairState
STATE_NAMES = tuple(s.name.lower() for s in PairState)

#: the largest Coulomb coefficient taken, from Python and from a scene file (beyond it the
#: loads overflow; measured metal pairs stay below about 1.5)
MAX_FRICTION = 10.0


class GrossSlidingError(InputError):
    """|Q| >= f P under force control: no static equilibrium exists."""


@attrs.frozen(eq=False)
class ContactState:
    """The pair unknowns at the end of an increment and the law's memory.

    Attributes
    ----------
    x : ndarray
        Pair unknowns (p, q, block displacements); read them with
        :meth:`fretbem.contact.unknowns.PairUnknowns.from_vector`.
    states : ndarray of int
        :class:`PairState` per pair.
    slip : ndarray
        Relative tangential displacement per pair (the stick reference of the next step).
    normal, tangential : float
        Loads P, Q reached.
    loads : mapping of str to float
        Named load amplitudes reached.
    virgin : bool
        True before the first increment (solvers then start from the gap-only state).
    memory : mapping of str to ndarray
        Further per-pair state of a law (e.g. wear depth); empty for Coulomb friction.
    """

    x: np.ndarray
    states: np.ndarray
    slip: np.ndarray
    normal: float = 0.0
    tangential: float = 0.0
    loads: Mapping[str, float] = attrs.field(factory=dict)
    virgin: bool = True
    memory: Mapping[str, np.ndarray] = attrs.field(factory=dict)

    @classmethod
    def initial(cls, problem) -> ContactState:
        """The unloaded state of ``problem`` (a condensed contact): all pairs separated, no slip."""
        n = problem.n_pairs
        return cls(
            x=np.zeros(problem.layout.size),
            states=np.full(n, PairState.SEPARATED, dtype=int),
            slip=np.zeros(n),
        )


@attrs.frozen(eq=False)
class LawEvaluation:
    """Complementarity functions and the pattern they were evaluated on.

    Attributes
    ----------
    normal, tangential : ndarray, shape (n,)
        F_n and F_t per pair.
    states : ndarray of int
        :class:`PairState` of each pair (the pattern of the piecewise-linear functions).
    direction : ndarray
        Sign of the trial tangential traction (slip direction on slipping pairs).
    """

    normal: np.ndarray
    tangential: np.ndarray
    states: np.ndarray
    direction: np.ndarray


class ContactLaw(ABC):
    """A contact law in complementarity form, as the solvers use it."""

    @abstractmethod
    def evaluate(
        self,
        p: np.ndarray,
        q: np.ndarray,
        gap: np.ndarray,
        slip: np.ndarray,
        r_n: float,
        r_t: float,
    ) -> LawEvaluation:
        """F_n, F_t and the pair states at tractions p, q, gap g and slip increment s."""

    @abstractmethod
    def jacobian_rows(
        self,
        evaluation: LawEvaluation,
        normal_map: np.ndarray,
        tangential_map: np.ndarray,
        r_n: float,
        r_t: float,
    ) -> np.ndarray:
        """Generalised Jacobian (2n, n_x) of (F_n, F_t) with respect to x, on the pattern of
        ``evaluation``; g and s are affine in x through ``normal_map`` / ``tangential_map``."""

    def coulomb_form(self) -> float | None:
        """The friction coefficient f when this law is Coulomb's cone with unilateral normal
        contact, else None. Solvers use it to reach their fast paths (the reduced Newton
        step, the LCP form of Lemke's method); a new law that is Coulomb's in disguise gets
        them by returning its f, any other law takes the general path."""
        return None

    def check_history(self, steps: Sequence[Any]) -> None:  # noqa: B027 - optional hook
        """Reject a load history this law cannot equilibrate (default: accept any)."""

    def evaluate_on(
        self,
        states: np.ndarray,
        direction: np.ndarray,
        p: np.ndarray,
        q: np.ndarray,
        gap: np.ndarray,
        slip: np.ndarray,
        r_n: float,
        r_t: float,
    ) -> LawEvaluation:
        """F_n, F_t continued affinely on a given pattern (states, slip directions).

        Optional: a Newton solver that starts an increment on the previous pattern needs the
        residual of that pattern, not of the pattern the start point falls in (they differ
        when the loads move every pair, e.g. a bulk stress). Laws without it get a Newton
        that starts from the pattern of the start point.
        """
        raise NotImplementedError


@attrs.frozen
class CoulombFriction(ContactLaw):
    """Coulomb friction with coefficient f, unilateral normal contact (Alart-Curnier).

    Attributes
    ----------
    friction : float
        Coulomb coefficient f >= 0.
    """

    friction: float = attrs.field(
        converter=number_field(
            "the Coulomb coefficient f",
            f"give 0 <= f <= {MAX_FRICTION:g} (0: frictionless; metals in fretting: about 0.3 "
            "to 1.5)",
            low=0.0,
            high=MAX_FRICTION,
        )
    )

    def coulomb_form(self) -> float:
        """f: this law is the Coulomb cone the solvers' fast paths are written for."""
        return self.friction

    def evaluate(self, p, q, gap, slip, r_n, r_t) -> LawEvaluation:
        """F_n, F_t (module docstring), states and slip directions."""
        normal_gap = r_n * gap
        augmented = p - normal_gap
        contact = augmented > 0
        trial = q + r_t * slip
        bound = self.friction * np.maximum(augmented, 0.0)
        # the bound is 0 off contact, so |trial| < bound only in contact; and there the
        # sliding F_t = q - bound sign(trial) is q exactly (q - 0)
        stick = np.abs(trial) < bound
        direction = np.sign(trial)
        f_n = np.where(contact, normal_gap, p)
        f_t = np.where(stick, -r_t * slip, q - bound * direction)
        # SEPARATED 0, STICK 1, SLIP 2 (PairState)
        states = np.where(contact, 2 - stick.astype(int), 0)
        return LawEvaluation(f_n, f_t, states, direction)

    def evaluate_on(self, states, direction, p, q, gap, slip, r_n, r_t) -> LawEvaluation:
        """The affine piece of F_n, F_t for the given pattern (see ContactLaw.evaluate_on)."""
        states = np.asarray(states)
        contact = states != PairState.SEPARATED
        stick, sliding = states == PairState.STICK, states == PairState.SLIP
        bound = self.friction * (p - r_n * gap)
        f_n = np.where(contact, r_n * gap, p)
        f_t = np.where(stick, -r_t * slip, np.where(sliding, q - bound * direction, q))
        return LawEvaluation(f_n, f_t, states, np.asarray(direction, float))

    def jacobian_rows(self, evaluation, normal_map, tangential_map, r_n, r_t) -> np.ndarray:
        """Rows of the generalised Jacobian: identity on separated pairs, r_n N on contact
        normal rows, -r_t T on stick rows, f sign (r_n N - e_p) + e_q on slip rows."""
        n, n_x = normal_map.shape
        states, direction = evaluation.states, evaluation.direction
        jac = np.zeros((2 * n, n_x))
        rows = np.arange(n)
        separated = states == PairState.SEPARATED
        stick, slip = states == PairState.STICK, states == PairState.SLIP
        contact = ~separated
        jac[rows[separated], rows[separated]] = 1.0
        jac[rows[contact]] = r_n * normal_map[contact]
        jac[n + rows[separated], n + rows[separated]] = 1.0
        jac[n + rows[stick]] = -r_t * tangential_map[stick]
        slip_rows = n + rows[slip]
        coeff = (self.friction * direction[slip])[:, None]
        jac[slip_rows] = coeff * r_n * normal_map[slip]
        jac[slip_rows, rows[slip]] -= coeff[:, 0]
        jac[slip_rows, slip_rows] += 1.0
        return jac

    def check_history(self, steps) -> None:
        """Under force control Coulomb friction needs f > 0 and |Q| < f P in every step.

        A step that imposes the tangential displacement (``delta``) is exempt: the block
        holds the body, and gross sliding at |Q| = f P is its solution. A step that imposes
        the approach is checked once its P is known (by the result checks)."""
        steps = [s for s in steps if getattr(s, "delta", None) is None]
        if not steps:
            return
        if self.friction == 0:
            raise GrossSlidingError(
                "the contact is frictionless (f = 0), so it cannot hold the upper body "
                "tangentially and under force control its tangential position is undetermined "
                "(no unique equilibrium); use a friction coefficient f > 0"
            )
        for step in steps:
            if step.normal is not None and abs(step.tangential) >= self.friction * step.normal:
                raise GrossSlidingError(
                    f"load step {step.name!r}: |Q| = {abs(step.tangential):g} >= f P = "
                    f"{self.friction * step.normal:g}, so no static equilibrium exists (gross "
                    "sliding); keep |Q| below f P under force control"
                )
