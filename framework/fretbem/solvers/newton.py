"""Solvers of one load increment of the condensed contact problem.

A :class:`Solver` finds the pair unknowns x = (p, q, block displacements) at which the
contact law holds at every pair and the loading blocks carry the prescribed forces; the
:class:`~fretbem.simulation.Simulation` calls :meth:`Solver.solve_increment` once per
increment, halving a failing increment up to ``max_substeps`` times.

:class:`SemiSmoothNewton` is the generalised Newton method on the Alart-Curnier functions
of the law: they are piecewise linear, so each step solves the exact linear problem of its
separated/stick/slip pattern, and the iteration ends when the residual is below the
tolerance, which happens once the pattern is right (docs/theory.md).
docs/how-to/new-solver.rst shows how to add a solver.
"""

from __future__ import annotations

import weakref
from abc import ABC, abstractmethod
from collections import deque

import attrs
import numpy as np
import scipy.linalg

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.law import (
    STATE_NAMES,
    ContactLaw,
    ContactState,
    CoulombFriction,
    LawEvaluation,
    PairState,
)
from fretbem.errors import ComputationError, SolverSettingsError
from fretbem.numerics.blas import one_blas_thread
from fretbem.validators import count_field, number_field

from . import newton_uncoupled
from .newton_linear import NewtonLinear
from .newton_uncoupled import UncoupledSteps

#: factor applied to the normal augmentation r_n when the Newton iteration cycles
CYCLE_SOFTENING = 0.1
#: the lean iteration (small uncoupled problems) guards reversals once a residual is above
#: this fraction of the one before: it has grown, or stalled at round-off
STALL = 1.0 - 1e-12
#: the pair states as plain ints (an IntEnum member costs an attribute lookup per use)
_STICK, _SLIP = int(PairState.STICK), int(PairState.SLIP)


def _newton_linear(
    kept: weakref.WeakKeyDictionary, problem: CondensedContact, law: ContactLaw, r_n, r_t
):
    """The reduced Newton linear solver of ``problem`` for a Coulomb law (None for others),
    kept in ``kept`` (the solver's own) between increments: an increment starts on the
    previous one's final pattern."""
    friction = law.coulomb_form()
    if friction is None:
        return None
    linear = kept.get(problem)
    if linear is None or not linear.matches(r_n, r_t, friction):
        maps = problem.normal_map, problem.tangential_map, problem.resultant_map
        part = newton_uncoupled.lean_part(*maps) if _plain_coulomb(law) else None
        if part is None:
            linear = NewtonLinear(*maps, friction, r_n, r_t)
        else:
            linear = UncoupledSteps(*maps, part, friction, r_n, r_t)
        kept[problem] = linear
    return linear


def _plain_coulomb(law: ContactLaw) -> bool:
    """Whether ``law`` evaluates F as CoulombFriction does (the lean iteration writes that
    arithmetic out; a subclass that changes it takes the general path)."""
    kind = type(law)
    return isinstance(law, CoulombFriction) and all(
        getattr(kind, name) is getattr(CoulombFriction, name)
        for name in ("evaluate", "evaluate_on", "jacobian_rows")
    )


def _largest(values: np.ndarray) -> float:
    """The largest of ``values`` (0 for none): ``values.max(initial=0.0)``'s number."""
    return np.maximum.reduce(values, initial=0.0)


#: (a ufunc reduction called directly)
_any = np.logical_or.reduce


class SolverConvergenceError(ComputationError):
    """A solver did not converge on an increment; the Simulation may then sub-step.

    Attributes
    ----------
    residuals : list of float
        The residual history of the failed attempt.
    """

    def __init__(self, message: str, residuals=()):
        super().__init__(message)
        self.residuals = list(residuals)


class NewtonConvergenceError(SolverConvergenceError):
    """The Newton iteration did not converge; carries the residual history and culprits.

    Attributes
    ----------
    residuals : list of float
    changing_pairs : ndarray of int
        Pairs whose contact state changed during the last iterations.
    """

    def __init__(self, message: str, residuals, changing_pairs):
        super().__init__(message, residuals)
        self.changing_pairs = np.asarray(changing_pairs)


@attrs.frozen(eq=False)
class IncrementResult:
    """Converged pair unknowns x = (p, q, deltas), pair states and iteration history."""

    x: np.ndarray
    states: np.ndarray
    iterations: int
    residuals: tuple[float, ...]


class Solver(ABC):
    """Solves one load increment of a condensed contact problem under a contact law.

    Attributes
    ----------
    max_substeps : int
        Times the Simulation may halve an increment this solver failed on
        (:class:`SolverConvergenceError`); 0 disables sub-stepping.
    displacement_control : bool
        Whether it solves steps that impose the block's displacement (default True).
    """

    max_substeps: int = 0
    #: whether the solver takes a loading block driven by displacement (a block row that
    #: constrains the block's own displacement instead of its force)
    displacement_control: bool = True

    @abstractmethod
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
        """The pair unknowns at the end of one increment.

        Parameters
        ----------
        problem : CondensedContact
            Relative displacements and block resultants as affine maps of x and loads.
        law : ContactLaw
            The contact law to satisfy at every pair.
        forces : ndarray, shape (2 m,)
            Forces the loading blocks must apply (problem.blocks order).
        loads : ndarray, shape (k,)
            Load amplitudes beta at the end of the increment (problem.load_names order).
        previous : ContactState
            The state at the start of the increment: its ``slip`` is the stick reference.
        start : ContactState or None
            Initial guess (None: the gap-only start, nothing known yet).

        Raises
        ------
        SolverConvergenceError
            If the increment could not be solved (the Simulation may then sub-step).
        """


def _tolerance(where: str, value: float) -> None:
    if not (0.0 < value <= 1e-3):
        raise SolverSettingsError(
            f"{where} must lie in (0, 1e-3] (a relative residual; the default 1e-10 "
            f"reproduces the published numbers), got {value!r}; give e.g. 1e-10"
        )


def _restore(cls, settings: dict):
    """A solver of ``cls`` rebuilt from its init settings (unpickling)."""
    return cls(**settings)


@attrs.frozen
class SemiSmoothNewton(Solver):
    """Semi-smooth (generalised) Newton method on the law's complementarity functions.

    Attributes
    ----------
    tolerance : float
        Relative tolerance on the complementarity and equilibrium residuals, in (0, 1e-3].
    max_iterations : int
        Newton iterations per increment before giving up (or sub-stepping), >= 1.
    max_substeps : int
        Times a failing increment may be halved automatically (0 disables sub-stepping).
    """

    tolerance: float = attrs.field(
        default=1e-10,
        converter=number_field(
            "the relative residual", "give e.g. 1e-10", check=_tolerance, error=SolverSettingsError
        ),
    )
    max_iterations: int = attrs.field(
        default=50,
        converter=count_field("give e.g. 50 (the default)", low=1, error=SolverSettingsError),
    )
    max_substeps: int = attrs.field(
        default=4,
        converter=count_field(
            "give e.g. 4 (the default; 0: no sub-stepping)", low=0, error=SolverSettingsError
        ),
    )
    #: the reduced Newton linear solver kept per condensed problem (weakly: a dropped
    #: problem frees it); the solver's own state, not the process's
    _linear: weakref.WeakKeyDictionary = attrs.field(
        init=False, factory=weakref.WeakKeyDictionary, repr=False, eq=False
    )

    #: the augmentation parameters (r_n, r_t) of each condensed problem, kept likewise
    _scales: weakref.WeakKeyDictionary = attrs.field(
        init=False, factory=weakref.WeakKeyDictionary, repr=False, eq=False
    )

    def _augmentation(self, problem: CondensedContact) -> tuple[float, float]:
        """r_n and r_t: the inverse mean diagonal compliances of the problem's own pairs
        (taken once per problem: every increment uses the same)."""
        scales = self._scales.get(problem)
        if scales is None:
            layout = problem.layout
            normal = np.abs(np.diag(problem.normal_map[:, layout.pressure]))
            tangential = np.abs(np.diag(problem.tangential_map[:, layout.shear]))
            # (np.mean's numbers, its sum by np.add.reduce over the count, without its frames)
            r_n = 1.0 / (np.add.reduce(normal) / normal.size)
            r_t = 1.0 / (np.add.reduce(tangential) / tangential.size)
            scales = self._scales[problem] = (r_n, r_t)
        return scales

    def __reduce__(self):
        """Pickled (and copied) by its settings: the kept linear solvers are this process's
        cache, in a weak dictionary that does not pickle; a copy starts without them."""
        settings = {f.name: getattr(self, f.name) for f in attrs.fields(type(self)) if f.init}
        return (_restore, (type(self), settings))

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
        """Solve one load increment from ``start`` (the gap-only start x = 0 if None).

        BLAS runs single-threaded here: the Newton systems are small (2 n + 2 unknowns), and
        threads competing for the cores of a busy machine made each solve 10-40x slower
        (benchmarks/performance.py: 1.65 s against 0.29 s for the 61-pair cycle).
        """
        with one_blas_thread():
            return self._solve_increment(problem, law, forces, loads, previous, start)

    @staticmethod
    def _newton_step(problem, law, evaluation, residual, r_n, r_t, linear) -> np.ndarray:
        """Solve J dx = -F: for Coulomb friction on the active rows only (separated and slip
        rows eliminated, through the LU of a nearby pattern: fretbem.solvers.newton_linear), else
        densely; lstsq if J is singular."""
        if linear is not None:
            try:
                return linear.step(residual, evaluation.states, evaluation.direction)
            except np.linalg.LinAlgError:
                pass
        jac = np.concatenate(
            [
                law.jacobian_rows(evaluation, problem.normal_map, problem.tangential_map, r_n, r_t),
                problem.resultant_map,
            ]
        )
        try:
            return np.linalg.solve(jac, -residual)
        except np.linalg.LinAlgError:
            # the minimum-norm least-squares step through a complete orthogonal factorisation
            # (QR with column pivoting): 2-5x cheaper than numpy's SVD-based lstsq
            return scipy.linalg.lstsq(jac, -residual, lapack_driver="gelsy")[0]

    def _solve_increment(self, problem, law, forces, loads, previous, start) -> IncrementResult:
        """The Newton iteration of :meth:`solve_increment`.

        From the gap-only start every pair is first taken closed and sticking, which makes
        the first linear system non-singular even for a body held only by contact.
        """
        n = problem.n_pairs
        layout = problem.layout
        r_n, r_t = self._augmentation(problem)
        forces = np.asarray(forces, float)
        linear = _newton_linear(self._linear, problem, law, r_n, r_t)
        if isinstance(linear, UncoupledSteps):
            return self._solve_uncoupled(problem, law, forces, loads, previous, start, r_n, r_t,
                                         linear)  # fmt: skip
        equations = _Equations(problem, law, problem.bases(loads), forces, previous.slip,
                               None if linear is None else linear.maps)  # fmt: skip
        x = np.zeros(layout.size) if start is None else np.array(start.x, dtype=float)
        residual, evaluation = equations.evaluate(x, r_n, r_t)
        if start is None:
            evaluation = attrs.evolve(evaluation, states=np.full(n, _STICK, dtype=int))
        else:
            residual, evaluation = equations.on_previous_pattern(x, r_n, r_t, start, residual,
                                                                 evaluation)  # fmt: skip
        history, state_history, seen = [], deque([evaluation.states.copy()], maxlen=6), set()
        force_scale = max(np.max(np.abs(forces), initial=0.0), 1e-300)
        tractions = layout.tractions
        guarded = False
        for iteration in range(1, self.max_iterations + 1):
            step = self._newton_step(problem, law, evaluation, residual, r_n, r_t, linear)
            x = x + step
            before = evaluation
            residual, evaluation = equations.evaluate(x, r_n, r_t)
            # (ufunc reductions called directly: ndarray.max's own frame costs as much here)
            traction_scale = max(_largest(np.abs(x[tractions])), 1e-300)
            size = np.abs(residual)
            norm = max(_largest(size[: 2 * n]) / traction_scale,
                       _largest(size[2 * n :]) / force_scale)  # fmt: skip
            history.append(float(norm))
            states = evaluation.states
            state_history.append(states.copy())
            if n and force_scale > 1e-300 and not np.logical_or.reduce(states):  # all SEPARATED
                raise _all_separated(iteration, history, n)
            # F is continuous across the separated/stick/slip boundaries, so a small residual
            # is a solution whichever side round-off puts a pair on. Pairs exactly at a limit
            # (|q| = f p with zero slip increment) flip state at round-off; requiring the
            # pattern to stop changing exhausted the iterations on dissimilar bodies.
            if norm <= self.tolerance:
                return IncrementResult(x, states, iteration, tuple(history))
            # F is affine on each pattern (states, slip directions), so the Newton iterate
            # depends on the pattern only: a pattern seen before means an endless cycle.
            # Break it by softening the normal augmentation r_n (F keeps the same roots).
            # once the residual grows, reversing pairs go through stick (through_stick)
            guarded = guarded or (len(history) > 1 and history[-1] > history[-2])
            if guarded:
                residual, evaluation = equations.through_stick(x, r_n, r_t, before, residual,
                                                               evaluation)  # fmt: skip
            if _seen_before(seen, evaluation.states, evaluation.direction):
                r_n *= CYCLE_SOFTENING
                linear = _newton_linear(self._linear, problem, law, r_n, r_t)
                residual, evaluation = equations.evaluate(x, r_n, r_t)
        raise self._not_converged(history, state_history)

    def _not_converged(self, history, state_history) -> NewtonConvergenceError:
        """The error of an increment that used up its iterations, naming the pairs whose
        state kept changing over the last ones."""
        recent = np.array(state_history)
        changing = np.flatnonzero(np.any(recent != recent[-1], axis=0))
        return NewtonConvergenceError(
            f"the contact Newton iteration did not converge in {self.max_iterations} iterations "
            f"(last residual {history[-1]:.3g}, tolerance {self.tolerance:.1g}); pairs "
            f"{changing.tolist()} kept changing state "
            f"({', '.join(STATE_NAMES[s] for s in np.unique(recent[:, changing]))}); set "
            "[contact] solver = 'lemke', split the steps into sub-increments ([load] "
            "increments; in Python LoadStep(increments=...) or "
            "SemiSmoothNewton(max_substeps=...)), or refine the contact discretisation",
            history,
            changing,
        )

    def _solve_uncoupled(self, problem, law, forces, loads, previous, start, r_n, r_t,
                         steps: UncoupledSteps) -> IncrementResult:  # fmt: skip
        """:meth:`_solve_increment`'s iteration on a small uncoupled problem, through
        :mod:`fretbem.solvers.newton_uncoupled`: the same iterates to round-off and the same
        guards (reversal through stick, from a stalled residual too; a repeated pattern
        softening r_n)."""
        n = problem.n_pairs
        increment = steps.increment(problem.bases(loads), forces, previous.slip)
        x = np.zeros(problem.layout.size) if start is None else np.array(start.x, dtype=float)
        increment.begin(x, problem.gap, None if start is None else start.states)
        history, state_history, seen = [], deque([increment.states], maxlen=6), set()
        force_scale = max(_largest(np.abs(forces)), 1e-300)
        guarded = False
        for iteration in range(1, self.max_iterations + 1):
            before_states, before_direction = increment.states, increment.direction
            exact = True
            try:
                step = increment.step()
            except np.linalg.LinAlgError:
                evaluation = LawEvaluation(increment.residual[:n], increment.residual[n : 2 * n],
                                           before_states, before_direction)  # fmt: skip
                step = self._newton_step(problem, law, evaluation, increment.residual,
                                         steps.r_n, r_t, None)  # fmt: skip
                exact = False
            norm = increment.advance(step, force_scale, exact)
            history.append(float(norm))
            states = increment.states
            state_history.append(states)
            # (a solved normal part keeps the contact set it was solved with: checked then)
            if n and force_scale > 1e-300 and not (increment.frozen or _any(states)):
                raise _all_separated(iteration, history, n)
            if norm <= self.tolerance:
                return IncrementResult(increment.x, states, iteration, tuple(history))
            # once the residual stops falling (a stall counts: an all-slip pattern that a
            # displacement-driven unloading step starts on keeps its residual, and whether
            # the next equal value reads an ulp above is round-off's choice)
            guarded = guarded or (len(history) > 1 and history[-1] > history[-2] * STALL)
            if guarded:
                increment.through_stick(before_states, before_direction)
            if _seen(seen, increment.pattern()):
                r_n *= CYCLE_SOFTENING
                steps = _newton_linear(self._linear, problem, law, r_n, r_t)
                increment.thaw(steps)
        raise self._not_converged(history, state_history)


def _seen_before(seen: set, states: np.ndarray, direction: np.ndarray) -> bool:
    """Whether the pattern (the states and the slipping pairs' slip directions: F's affine
    piece) was met before in the increment, which then starts a new set; else it is added."""
    return _seen(seen, (states.tobytes(), direction[states == _SLIP].tobytes()))


def _seen(seen: set, pattern: tuple) -> bool:
    """:func:`_seen_before` of a pattern given as its key (states, slipping directions)."""
    if pattern in seen:
        seen.clear()
        return True
    seen.add(pattern)
    return False


def _all_separated(iteration: int, history, n: int) -> NewtonConvergenceError:
    """The error of an iteration that separated every pair while the blocks carry a force:
    the next step would move a block held by nothing (a near-singular system); the
    Simulation may sub-step the increment."""
    return NewtonConvergenceError(
        f"the contact Newton iteration separated every pair at iteration "
        f"{iteration} although the loading blocks carry a force; set [contact] "
        "solver = 'lemke', or split the steps into sub-increments ([load] "
        "increments; in Python LoadStep(increments=...) or "
        "SemiSmoothNewton(max_substeps=...))",
        history,
        np.arange(n),
    )


class _Equations:
    """F(x) of one increment: the law's functions and the block rows at fixed loads.

    What does not change within the increment (the gap at x = 0, the bases, the maps, the
    slices of x) is taken once; each evaluation keeps its gap and slip, which the pattern
    continuations (:meth:`on_previous_pattern`, :meth:`through_stick`) reuse.
    """

    def __init__(self, problem: CondensedContact, law: ContactLaw, bases, forces, slip,
                 maps=None):  # fmt: skip
        normal_base, self.tangential_base, self.resultant_base = bases
        #: the Newton linear solver's maps, whose products skip all-zero column ranges
        self.maps = maps
        self.law, self.forces, self.reference_slip = law, forces, slip
        self.n = problem.n_pairs
        self.gap_base = problem.gap + normal_base
        self.normal_map = problem.normal_map
        self.tangential_map = problem.tangential_map
        self.resultant_map = problem.resultant_map
        self.pressure, self.shear = problem.layout.pressure, problem.layout.shear
        self.gap = self.slip = None

    def evaluate(self, x: np.ndarray, r_n: float, r_t: float):
        """F(x) (a new array) and the law's evaluation at x; keeps x's gap and slip."""
        maps = self.maps
        if maps is not None and maps.together is not None:  # small: one product for all three
            n = self.n
            products = maps.together @ x
            gap = self.gap_base + products[:n]
            slip = self.tangential_base + products[n : 2 * n] - self.reference_slip
            blocks = self.resultant_base + products[2 * n :] - self.forces
        else:
            if maps is None:
                gap = self.gap_base + self.normal_map @ x
                slip = self.tangential_base + self.tangential_map @ x - self.reference_slip
            else:
                normal, tangential = maps.both_times(x)
                gap = self.gap_base + normal
                slip = self.tangential_base + tangential - self.reference_slip
            blocks = self.resultant_base + self.resultant_map @ x - self.forces
        self.gap, self.slip = gap, slip
        evaluation = self.law.evaluate(x[self.pressure], x[self.shear], gap, slip, r_n, r_t)
        return np.concatenate([evaluation.normal, evaluation.tangential, blocks]), evaluation

    def _on(self, states, direction, x, r_n, r_t, residual):
        """Residual and evaluation continued on the pattern (states, direction) at the x of
        the last :meth:`evaluate`; NotImplementedError if the law has no continuation."""
        pattern = self.law.evaluate_on(states, direction, x[self.pressure], x[self.shear],
                                       self.gap, self.slip, r_n, r_t)  # fmt: skip
        n = self.n
        out = residual.copy()
        out[:n] = pattern.normal
        out[n : 2 * n] = pattern.tangential
        return out, pattern

    def on_previous_pattern(self, x, r_n, r_t, start: ContactState, residual, evaluation):
        """Residual and pattern of the first iteration: the previous increment's pattern.

        The first Newton step then solves that pattern's linear problem exactly. Its
        residual must be the same pattern's (not the pattern the start point falls in,
        which a load that moves every pair, like a bulk stress, changes wholesale).
        ``residual`` and ``evaluation`` are the last :meth:`evaluate`'s, at x.
        """
        states = np.asarray(start.states)
        q = x[self.shear]
        direction = np.where(q != 0.0, np.sign(q), evaluation.direction)
        try:
            return self._on(states, direction, x, r_n, r_t, residual)
        except NotImplementedError:
            return residual, attrs.evolve(evaluation, states=states)

    def through_stick(self, x, r_n, r_t, before, residual, evaluation):
        """Residual and pattern of the next step, with no pair reversing its slip in one step.

        A pair that slipped one way and whose trial traction now points the other way is
        taken sticking for the next step (its residual on that pattern): it reverses through
        stick, as it does physically. Without this, when the stick window of the trial
        traction, 2 f p / r_t, is narrow against the slip a step produces (r_t grows like
        1 / (h log h) with the pair spacing h), an unloading step's reversing pairs jump from
        slip to opposite slip, the stick zone drains away iteration after iteration and the
        all-slip pattern is singular (the 481-pair half-plane cycle: 50 iterations and
        4 halvings per unloading step). The solver applies it once the residual has grown
        in an increment: a direct reversal is right for most pairs of a coarse contact and
        saves an iteration there (the reference numbers are those of the plain iteration).
        ``residual`` and ``evaluation`` are the last :meth:`evaluate`'s, at x.
        """
        was = (before.states == _SLIP) & (evaluation.states == _SLIP)
        reversing = was & (before.direction * evaluation.direction < 0)
        if not reversing.any():
            return residual, evaluation
        states = np.where(reversing, _STICK, evaluation.states)
        try:
            return self._on(states, evaluation.direction, x, r_n, r_t, residual)
        except NotImplementedError:
            return residual, evaluation
