"""The Newton iteration of a small contact problem whose normal part is uncoupled, lean.

Two bodies of one elastic material (Dundurs' beta = 0: the half-plane body model of equal
materials, for one) make the gap independent of the shears, so the Newton Jacobian is
block lower triangular: each step solves the normal block (pressures of the pairs in
contact, the normal block components) and then the tangential one (shears of the sticking
pairs, the tangential block components) with the normal update among its known values
(:func:`lean_part` tells the blocks apart).

The normal iterates do not depend on the tangential ones, and a step solves its pattern's
affine equations exactly: once the contact set found after a step is the one the step was
taken on, the normal part is solved (to round-off) and stays so. From then on (``frozen``)
an iteration evaluates and solves the tangential part only, where the general path
(:class:`~fretbem.solvers.newton_linear.NewtonLinear` and the law's evaluation) solves
the normal block again at every iteration for round-off corrections; a cycle at constant P
solves its normal problem once per step. F(x) is the Coulomb law's, written out as
:class:`~fretbem.contact.law.CoulombFriction` evaluates it; the index sets of each
pattern and the LU of each contact and stick set are kept.

The iterates are the general path's to round-off and take as many iterations, or fewer
where the residual stalls (the solver's reversal guard then applies from the first equal
residual: fretbem.solvers.newton.STALL). Systems of :data:`LEAN_BELOW` unknowns or more,
coupled problems and other laws take the general path
(tests/framework/solvers/test_newton_uncoupled.py, benchmarks/uncoupled_newton_trees.py).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from . import newton_linear
from .newton_linear import _lu

#: systems of fewer unknowns take the lean iteration (the size below which NewtonLinear
#: factorises every pattern afresh: its per-pattern objects then cost more than the LUs)
LEAN_BELOW = newton_linear.DIRECT_BELOW
#: coupling entries at most this fraction of their map's largest entry are round-off: two
#: half-planes of one material on faces discretised differently (a rounded-flat pad on a
#: flat) add the Dundurs terms of each body, which cancel to about 1e-16 of the map, not 0.
#: Dissimilar materials couple at about beta (1e-2 to 0.3), faces paired by interpolation
#: (a track longer than the pad's face) at about 1e-3
ROUND_OFF = 1e-12
#: pair states, as in the contact law (SEPARATED, STICK, SLIP)
_SEPARATED, _STICK, _SLIP = 0, 1, 2
#: patterns and LU factors kept (the oldest dropped first): at most this many LUs of fewer
#: than LEAN_BELOW unknowns each, 6.5 MB at most
KEPT_FACTORS = 32
#: ufunc reductions called directly (an ndarray method's own frame costs as much here)
_largest_of, _any, _all = np.maximum.reduce, np.logical_or.reduce, np.logical_and.reduce
_largest_at = np.maximum.reduceat
_getrs = sla.lapack.dgetrs
#: matrix times vector: np.dot makes the same BLAS call as the @ operator (the same numbers)
#: for about 2,000 fewer instructions a call than the matmul ufunc's dispatch
_dot = np.dot


def _largest(values: np.ndarray) -> float:
    """The largest of ``values`` (0 for none)."""
    return _largest_of(values, initial=0.0)


def _largest_of_each(values: np.ndarray, cuts: tuple) -> tuple:
    """:func:`_largest` of ``values[:cut]`` and ``values[cut:]`` (``cuts`` = [0, cut], or
    [0] where the second is empty), of non-negative ``values``: the same numbers from one
    reduction."""
    if len(cuts) == 1:
        return _largest(values), 0.0
    return _largest_at(values, cuts)


def lean_part(normal_map, tangential_map, resultant_map) -> tuple | None:
    """Which block rows and which block columns belong to the normal problem (two boolean
    arrays over the block components) of a system the lean iteration takes, else None.

    Taken: fewer than :data:`LEAN_BELOW` unknowns, and uncoupled up to round-off (entries
    at most :data:`ROUND_OFF` of their map's largest read as 0; F is always evaluated with
    every entry, the lean step leaves them out of the normal block, whose iterates they
    would move by about that fraction). A block column is tangential if a slip row sees it;
    a block row if it sees a shear or a tangential block column. Uncoupled: no gap row sees
    a tangential column, and the normal block rows are as many as its columns. Unlike
    :func:`~fretbem.solvers.newton_linear.normal_part` a block row need not be its
    column's: a step driven by delta or by the approach makes the block's force row of one
    direction a displacement row of the other.
    """
    n, n_x = normal_map.shape
    if n == 0 or n_x >= LEAN_BELOW or resultant_map.shape[0] != n_x - 2 * n:
        return None
    normal, tangential, resultant = (_nonzero(m) for m in (normal_map, tangential_map,
                                                          resultant_map))  # fmt: skip
    blocks = np.arange(2 * n, n_x)
    columns = ~tangential[:, blocks].any(axis=0)  # the normal block columns
    seen = np.zeros(n_x, dtype=bool)  # the tangential columns
    seen[n : 2 * n] = True
    seen[blocks[~columns]] = True
    rows = ~resultant[:, seen].any(axis=1)
    # no gap row sees a tangential column: the shear ones read as a slice, not a gathered copy
    hit = normal[:, n : 2 * n].any() or normal[:, blocks[~columns]].any()
    if hit or rows.sum() != columns.sum():
        return None
    return rows, columns


def _nonzero(matrix: np.ndarray) -> np.ndarray:
    """Where ``matrix`` is more than round-off (:data:`ROUND_OFF` of its largest entry)."""
    size = np.abs(matrix)
    return size > ROUND_OFF * _largest(size.ravel())


class UncoupledSteps:
    """What the lean iteration keeps of one small uncoupled problem: its stacked maps, the
    index sets of each pattern met and the LU factors of each contact and stick set.

    Parameters
    ----------
    normal_map, tangential_map, resultant_map : ndarray
        The condensed problem's maps (n, n_x), (n, n_x), (n_x - 2 n, n_x).
    part : tuple of ndarray of bool
        Which block rows and columns are the normal problem's (:func:`lean_part`).
    friction, r_n, r_t : float
        Coulomb coefficient and augmentation parameters.
    """

    def __init__(self, normal_map, tangential_map, resultant_map, part, friction, r_n, r_t):
        n, n_x = normal_map.shape
        self.n, self.n_x = n, n_x
        self.friction, self.r_n, self.r_t = float(friction), float(r_n), float(r_t)
        #: (N; T; R): F(x)'s three products in one
        self.together = np.concatenate([normal_map, tangential_map, resultant_map])
        #: the Jacobian's contact rows (r_n N; -r_t T; R): ``together``'s rows times their
        #: factors in one product (each entry the same product as scaling each map alone)
        scale = np.ones((len(self.together), 1))
        scale[:n], scale[n : 2 * n] = self.r_n, -self.r_t
        self.stacked = self.together * scale
        blocks = np.arange(2 * n, n_x)
        rows, columns = part
        #: the block rows and columns (numbers of x) of the normal and tangential problems
        self.normal_rows, self.tangential_rows = blocks[rows], blocks[~rows]
        self.normal_columns, self.tangential_columns = blocks[columns], blocks[~columns]
        #: (T; R's tangential rows): F's products once the normal part is solved
        self.tangential_maps = np.concatenate(
            [tangential_map, resultant_map[self.tangential_rows - 2 * n]]
        )
        self.normal_map, self.tangential_map = normal_map, tangential_map
        #: where the residual's measure splits: the pair rows (0, 2 n) and block rows; and,
        #: once the normal part is solved, the slip rows and the tangential block rows
        self.cuts = np.array([0, 2 * n] if n_x > 2 * n else [0])
        #: the tangential block rows among the block rows; 0.0 and the states SEPARATED,
        #: STICK and SLIP at every pair, operands of the evaluations and of the patterns'
        #: index sets (an array operand, not a Python scalar, spares numpy's scalar
        #: conversion on every call)
        self.tangential_blocks = self.tangential_rows - 2 * n
        self.zeros = np.zeros(n)
        self.zeros_int, self.ones, self.twos = (
            np.full(n, state) for state in (_SEPARATED, _STICK, _SLIP)
        )
        for operand in (self.zeros, self.zeros_int, self.ones, self.twos):
            operand.setflags(write=False)
        self.measured = np.concatenate([np.arange(n, 2 * n), self.tangential_rows])
        self.measured_cuts = np.array([0, n] if self.tangential_rows.size else [0])
        self.factorisations = 0
        self._patterns: dict[bytes, tuple] = {}
        self._factors: dict[bytes, tuple] = {}

    def matches(self, r_n: float, r_t: float, friction: float) -> bool:
        """Whether this was built for these augmentation parameters and friction."""
        return (self.r_n, self.r_t, self.friction) == (r_n, r_t, friction)

    def indices(self, states: np.ndarray) -> tuple:
        """Separated and slipping pairs (their pressures, their shears' numbers in x), and
        the rows and columns of the normal block (the gap rows of the pairs in contact and
        the normal block rows; their pressures and the normal block columns) and of the
        tangential one (the slip rows of the sticking pairs, the tangential block rows;
        their shears, the tangential block columns) of the pattern ``states`` (kept)."""
        key = states.tobytes()
        found = self._patterns.get(key)
        if found is None:
            n = self.n
            separated = (states == self.zeros_int).nonzero()[0]
            slipping = (states == self.twos).nonzero()[0]
            contact = states.nonzero()[0]  # (not SEPARATED, 0)
            stick = n + (states == self.ones).nonzero()[0]
            found = (
                separated, slipping, n + separated, n + slipping,
                np.concatenate([contact, self.normal_rows]),
                np.concatenate([contact, self.normal_columns]),
                np.concatenate([stick, self.tangential_rows]),
                np.concatenate([stick, self.tangential_columns]),
            )  # fmt: skip
            _keep(self._patterns, key, found)
        return found

    def factor(self, rows: np.ndarray, columns: np.ndarray) -> tuple:
        """The LU of the Jacobian's block ``rows`` x ``columns`` (kept per row set: the
        columns follow from the rows); LinAlgError if singular."""
        key = rows.tobytes()
        found = self._factors.get(key)
        if found is None:
            found = _lu(self.stacked.take(rows, axis=0).take(columns, axis=1))
            self.factorisations += 1
            _keep(self._factors, key, found)
        return found

    def increment(self, bases, forces: np.ndarray, slip: np.ndarray) -> UncoupledIncrement:
        """The equations of one increment: bases (normal, tangential, resultant) at its
        loads, the forces its block rows impose and the stick reference ``slip``."""
        return UncoupledIncrement(self, bases, forces, slip)


def _keep(kept: dict, key: bytes, value) -> None:
    if len(kept) >= KEPT_FACTORS:
        del kept[next(iter(kept))]
    kept[key] = value


def _solved(lu, piv, rhs: np.ndarray) -> np.ndarray:
    """y with matrix y = rhs from the factors of ``newton_linear._lu`` (LAPACK's getrs)."""
    if rhs.shape[0] == 0:
        return rhs
    u, info = _getrs(lu, piv, rhs, trans=1)
    if info != 0:  # pragma: no cover - LAPACK argument error
        raise np.linalg.LinAlgError("reduced Newton solve failed")
    return u


class UncoupledIncrement:
    """F(x), its pattern and the Newton steps of one increment (x held here).

    After :meth:`begin`, ``residual`` is F at ``x`` on the pattern (``states``,
    ``direction``) the next step solves.
    """

    def __init__(self, steps: UncoupledSteps, bases, forces, slip):
        normal_base, tangential_base, resultant_base = bases
        self.steps = steps
        n = steps.n
        self.gap_base = None
        self._normal_base = normal_base
        #: the slip and block rows at x = 0 (slip less the stick reference, resultants less
        #: the imposed forces)
        self.slip_base = tangential_base - slip
        self.block_base = resultant_base - forces
        self.n = n
        self.x = self.residual = self.states = self.direction = None
        self.gap = self.slip = self.bound = self.contact = None
        #: whether the normal part is solved (its unknowns, F and pattern kept)
        self.frozen = False
        self._normal_size = 0.0
        self._tangential_base = self.block_base[steps.tangential_blocks]

    def begin(self, x: np.ndarray, gap: np.ndarray, states=None) -> None:
        """Start at ``x`` (owned from now on) with the problem's ``gap`` (at x = 0): F on
        the gap-only start's pattern (every pair sticking) if ``states`` is None, else on
        the pattern ``states`` with the slip directions of the shears at x (the previous
        increment's pattern: its affine F, not the pattern x falls in)."""
        self.gap_base = gap + self._normal_base
        self.x = x
        if states is None:
            self.evaluate()
            self.states = np.full(self.n, _STICK, dtype=int)
            return
        # F on the pattern alone: the gap, slip and block rows at x and the trial
        # tractions' directions (evaluate's numbers; its pattern would be replaced)
        steps, n = self.steps, self.n
        products = _dot(steps.together, x)
        self.gap = self.gap_base + products[:n]
        slip = self.slip = self.slip_base + products[n : 2 * n]
        q = x[n : 2 * n]
        trial = np.sign(q + steps.r_t * slip)
        direction = np.where(q != 0.0, np.sign(q), trial)
        self._continue_on(np.asarray(states), direction, self.block_base + products[2 * n :])

    def evaluate(self) -> None:
        """F at x and its pattern (CoulombFriction.evaluate's arithmetic)."""
        steps, n, x = self.steps, self.n, self.x
        r_n, r_t = steps.r_n, steps.r_t
        products = _dot(steps.together, x)
        gap = self.gap = self.gap_base + products[:n]
        slip = self.slip = self.slip_base + products[n : 2 * n]
        blocks = self.block_base + products[2 * n :]
        p, q = x[:n], x[n : 2 * n]
        normal_gap = r_n * gap
        augmented = p - normal_gap
        contact = self.contact = augmented > 0.0
        trial = q + r_t * slip
        bound = self.bound = steps.friction * np.maximum(augmented, steps.zeros)
        stick = np.abs(trial) < bound
        self.direction = np.sign(trial)
        f_n = np.where(contact, normal_gap, p)
        f_t = np.where(stick, -r_t * slip, q - bound * self.direction)
        # SEPARATED 0, STICK 1, SLIP 2; stick only in contact (the bound is 0 elsewhere)
        self.states = contact * steps.twos - stick
        self.residual = np.concatenate([f_n, f_t, blocks])

    def _evaluate_tangential(self) -> None:
        """F's tangential part and the pattern at x, the normal part being solved."""
        steps, n, x = self.steps, self.n, self.x
        r_t = steps.r_t
        products = _dot(steps.tangential_maps, x)
        slip = self.slip = self.slip_base + products[:n]
        q = x[n : 2 * n]
        trial = q + r_t * slip
        stick = np.abs(trial) < self.bound
        direction = self.direction = np.sign(trial)
        residual = self.residual
        residual[n : 2 * n] = np.where(stick, -r_t * slip, q - self.bound * direction)
        residual[steps.tangential_rows] = self._tangential_base + products[n:]
        self.states = self._contact_states - stick

    def _continue_on(self, states: np.ndarray, direction: np.ndarray, blocks) -> None:
        """F continued on the pattern (states, direction) at x, with the block rows
        ``blocks`` (CoulombFriction.evaluate_on's arithmetic)."""
        steps, n, x = self.steps, self.n, self.x
        r_n, r_t = steps.r_n, steps.r_t
        p, q, gap = x[:n], x[n : 2 * n], self.gap
        contact = states.astype(bool)  # (not SEPARATED, 0)
        stick, sliding = states == steps.ones, states == steps.twos
        bound = steps.friction * (p - r_n * gap)
        self.residual = np.concatenate([
            np.where(contact, r_n * gap, p),
            np.where(stick, -r_t * self.slip, np.where(sliding, q - bound * direction, q)),
            blocks,
        ])  # fmt: skip
        self.states, self.direction = states, np.asarray(direction, float)

    def pattern(self) -> tuple[bytes, bytes]:
        """The current pattern's key (the states and the slipping pairs' slip directions:
        F's affine piece), as fretbem.solvers.newton._seen_before forms it; the pattern's
        index sets are kept for the next step."""
        states = self.states
        slipping = self.steps.indices(states)[1]
        return states.tobytes(), self.direction[slipping].tobytes()

    def through_stick(self, before_states: np.ndarray, before_direction: np.ndarray) -> None:
        """Pairs that slipped one way at the last pattern and now the other stick for the
        next step (fretbem.solvers.newton._Equations.through_stick says why)."""
        states = self.states
        twos = self.steps.twos  # (SLIP)
        reversing = ((before_states == twos) & (states == twos)
                     & (before_direction * self.direction < 0))  # fmt: skip
        if reversing.any():
            self._continue_on(np.where(reversing, _STICK, states), self.direction,
                              self.residual[2 * self.n :])  # fmt: skip

    def step(self) -> np.ndarray:
        """dx with J dx = -F on the current pattern (the normal part's 0 once solved);
        LinAlgError if a reduced matrix is singular. A block whose right-hand side is all
        zero (the shears under a normal load alone) is 0 without its factor."""
        steps = self.steps
        (separated, slipping, separated_q, slipping_q, normal_rows, normal_columns,
         tangential_rows, tangential_columns) = steps.indices(self.states)  # fmt: skip
        stacked = steps.stacked
        b = -self.residual
        y = np.zeros(steps.n_x)
        if not self.frozen:
            rhs = b[normal_rows]
            if separated.size:
                y[separated] = b[separated]
                rhs -= _dot(stacked, y)[normal_rows]
            if _any(rhs):
                y[normal_columns] = _solved(*steps.factor(normal_rows, normal_columns), rhs)
        # a separated pair's shear goes to 0, a slipping pair's follows its pressure:
        # dq_i = c_i (dp_i + F_n[i]) - F_t[i]
        y[separated_q] = b[separated_q]
        coeff = steps.friction * self.direction[slipping]
        y[slipping_q] = b[slipping_q] + coeff * (y[slipping] - b[slipping])
        rhs = b[tangential_rows] - _dot(stacked, y)[tangential_rows]
        if _any(rhs):
            y[tangential_columns] = _solved(*steps.factor(tangential_rows, tangential_columns),
                                            rhs)  # fmt: skip
        return y

    def advance(self, dx: np.ndarray, force_scale: float, exact: bool = True) -> float:
        """x + dx, F and the pattern there; returns the relative residual (the larger of
        the pair functions over the largest traction and of the block rows over the
        largest force). ``exact``: dx solved the step's pattern exactly (not a
        least-squares step), so the normal part is solved if its contact set holds."""
        n = self.n
        self.x += dx
        if self.frozen and exact:
            self._evaluate_tangential()
        else:  # (a least-squares step moves the normal part too: F afresh)
            stepped = self.states.astype(bool)  # (in contact: not SEPARATED, 0)
            self.frozen = False
            self.evaluate()
            if exact and _all(self.contact == stepped):
                self._freeze()
        x, steps = self.x, self.steps
        size = np.abs(self.residual)
        if self.frozen:  # (the slip rows' and the tangential block rows' largest in one)
            traction = max(self._pressure_scale, _largest(np.abs(x[n : 2 * n])))
            pairs, blocks = _largest_of_each(size.take(steps.measured), steps.measured_cuts)
            pairs, blocks = max(self._normal_size, pairs), max(self._block_size, blocks)
        else:
            traction = _largest(np.abs(x[: 2 * n]))
            pairs, blocks = _largest_of_each(size, steps.cuts)
        traction = max(traction, 1e-300)
        return max(pairs / traction, blocks / force_scale)

    def _freeze(self) -> None:
        n = self.n
        self.frozen = True
        self._contact_states = self.contact * self.steps.twos
        size = np.abs(self.residual)
        self._normal_size = _largest(size[:n])
        self._block_size = _largest(size[self.steps.normal_rows])
        self._pressure_scale = _largest(np.abs(self.x[:n]))

    def thaw(self, steps: UncoupledSteps) -> None:
        """Go on with ``steps`` (other augmentation parameters) from x: F there afresh."""
        self.steps, self.frozen = steps, False
        self.evaluate()
