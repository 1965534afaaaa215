"""The semi-smooth Newton step of the contact solver, reduced to its active rows.

The generalised Jacobian of the Alart-Curnier functions has three kinds of pair rows
(unknowns x = (p, q, block displacements), n pairs):

- separated pair i: identity rows, so dp_i = -F_n[i] and dq_i = -F_t[i];
- slip pair i: the tangential row is c_i times the normal row minus c_i e_i plus e_(n+i),
  c_i = f sign(trial), so with the normal row's equation, dq_i = c_i (dp_i + F_n[i]) - F_t[i];
- contact (stick or slip) normal rows r_n N_i and stick tangential rows -r_t T_i stay.

Eliminating the first two leaves a dense system over (dp of pairs in contact, dq of
sticking pairs, block displacements) only: (n_contact + n_stick + m) unknowns instead of
2 n + m, and the same step to round-off (tests/framework/test_newton_linear.py).

Successive Newton iterations change the pattern of only a few pairs, so
:class:`NewtonLinear` keeps the LU of one pattern's reduced matrix and solves a nearby
pattern's system through it, bordered by the few rows that differ (a Schur complement of
their size), refactorising when too many rows differ or the bordered solve loses accuracy.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

#: pair states, as in the contact law (SEPARATED, STICK, SLIP)
_SEPARATED, _STICK, _SLIP = 0, 1, 2
#: refactorise when the border (rows that differed since the last LU) outgrows this fraction
#: of the factorised system (and MIN_BORDER): its columns then cost about a new LU. Steps
#: of the 961-pair cycle, CPU s: 2.04 refactorising every iteration, 1.05 at 0.12, 0.96 at
#: 0.2, 0.93 at 0.3 (4 LUs instead of 41)
BORDER_FRACTION = 0.3
MIN_BORDER = 16
#: the same for the split factor of identical bodies, whose new LU is the tangential block's
#: alone while the contact set holds (about an eighth of the coupled one), and only once a
#: shear needs it. Steps of the half-plane reference cycle, CPU ms, medians of 7 alternating
#: runs in one process (load 10): 481 pairs 90.7 at 0.15, 86.4 at 0.1, 85.2 at 0.08, 83.6 at
#: 0.05; 961 pairs 394 at 0.15, 381 at 0.1, 372 at 0.08, 368 at 0.05 (a second run: 0.05 to
#: 0.0 within the noise, 5 %); iterations unchanged (benchmarks/split_border_fraction.py)
SPLIT_BORDER_FRACTION = 0.08
#: systems of fewer unknowns are factorised afresh every step: their LU (about 70 us at
#: 120 unknowns) costs less than the bordered solve's bookkeeping
DIRECT_BELOW = 160
#: systems of at least this many unknowns skip the zero column ranges of uncoupled maps in
#: their products (and form N x and T x in one); below, numpy's fixed cost per call outweighs
#: the halved products. Steps of the half-plane reference cycle, split factor and products
#: over coupled in one process (load 7-12): 1.07 at 61 pairs, 1.12 at 121, 0.85 at 241, 0.69
#: at 481. The split factor alone pays below it too (its normal block kept while the contact
#: set holds, the tangential block about a quarter of the coupled LU), so it is used at every
#: size: 0.91 at 61 pairs, 0.89 at 121, 0.75 at 181 (load 10-12, 20-40 alternating runs;
#: benchmarks/split_small_systems.py)
SPLIT_FROM = 400
#: a factor replaced by one of at most this fraction of its order is kept aside (its LU
#: then holds at most a ninth more memory than the one factor) and taken back when a
#: pattern lies closer to it: the first increment of a cycle goes from every pair in
#: contact (the start) to the few the load touches and back to every pair, whose LU the
#: step then reuses, as it is, where it was factorised anew (481 pairs, BEM bodies: one
#: LU of 964 unknowns, 20 ms of the cycle's 170 ms of steps; the same step bit for bit)
SPARE_FRACTION = 0.3
#: a bordered solve is accepted when its residual is below this fraction of the size of
#: the row products (a direct LU solve leaves about 1e-15)
ACCEPT_RESIDUAL = 1e-12


#: ndarray.any and .all's reductions called directly: their own Python frame costs as much as
#: the work on a few hundred numbers, and the Newton step asks several times an iteration
_any, _all = np.logical_or.reduce, np.logical_and.reduce
#: no rows (a factor's border before any)
_NO_ROWS = np.zeros(0, dtype=int)
_NO_ROWS.setflags(write=False)


class _Pattern:
    """States and slip coefficients of the pairs: which rows the Jacobian has."""

    def __init__(self, states: np.ndarray, direction: np.ndarray, friction: float):
        self.states = np.asarray(states)
        self.contact = self.states != _SEPARATED
        self.stick = self.states == _STICK
        self.slip = self.states == _SLIP
        self.coeff = np.where(self.slip, friction * np.asarray(direction, float), 0.0)
        self.c = self.contact.nonzero()[0]
        self.s = self.stick.nonzero()[0]

    def same(self, other: _Pattern) -> bool:
        """Whether both patterns give the same Jacobian (states and slip coefficients)."""
        return bool(_all(self.states == other.states) and _all(self.coeff == other.coeff))

    def differing_rows(self, other: _Pattern) -> np.ndarray:
        """Row numbers (of the 2 n pair rows) where this pattern's Jacobian differs."""
        normal = self.contact != other.contact
        tangential = (self.states != other.states) | (self.slip & (self.coeff != other.coeff))
        n = self.states.size
        return np.concatenate([normal.nonzero()[0], n + tangential.nonzero()[0]])


class _Maps:
    """The condensed maps and augmentation parameters the Jacobian rows are made of."""

    def __init__(self, normal_map, tangential_map, resultant_map, r_n: float, r_t: float):
        self.normal, self.tangential, self.resultant = normal_map, tangential_map, resultant_map
        self.r_n, self.r_t = float(r_n), float(r_t)
        self.n, self.n_x = normal_map.shape
        #: the numbers of x of the block components (after the 2 n pair unknowns)
        self.blocks = np.arange(2 * self.n, self.n_x)
        #: the Jacobian's contact rows stacked (r_n N; -r_t T; R), for small systems only
        #: (their reduced matrix is then one gather of it; a large one would double memory)
        self.stacked = self.together = None
        if self.n_x < DIRECT_BELOW:
            self.stacked = np.concatenate(
                [self.r_n * normal_map, -self.r_t * tangential_map, resultant_map]
            )
            #: (N; T; R) stacked: F(x)'s three products in one (small systems)
            self.together = np.concatenate([normal_map, tangential_map, resultant_map])
        #: the numbers of x (equations and unknowns alike) of the normal problem when it does
        #: not depend on the tangential one (None if it does): see :func:`normal_part`
        #: (the factor splits at every size; the products only from SPLIT_FROM)
        large = self.n_x >= SPLIT_FROM
        self.normal_part = normal_part(normal_map, tangential_map, resultant_map)
        #: the column ranges (pressures, shears, blocks) where N and T are not all zero: the
        #: products skip the rest (identical bodies: the shear columns of N, the pressure
        #: columns of T, half of each product)
        self.normal_ranges = _nonzero_ranges(normal_map, self.n) if large else None
        #: whether a tangential row (slip, tangential block) has a non-zero in a normal
        #: column (the split's coupling is then not zero by structure)
        self.tangential_sees_normal = self.normal_part is not None and bool(
            tangential_map[:, self.normal_part].any()
            or resultant_map[~self.normal_part[2 * self.n :]][:, self.normal_part].any()
        )
        self.tangential_ranges = _nonzero_ranges(tangential_map, self.n) if large else None
        #: the same per column (None: all used), for products over a few columns
        self.normal_used = _used_columns(normal_map, self.normal_ranges)
        self.tangential_used = _used_columns(tangential_map, self.tangential_ranges)
        #: N's pressure block, when T's shear block is minus it bit for bit and the other
        #: two are zero (identical bodies); None otherwise: see :meth:`both_times`
        self.mirrored = _mirrored(normal_map, tangential_map) if large else None

    def normal_times(self, x: np.ndarray) -> np.ndarray:
        """N x, over N's non-zero column ranges only."""
        return _product(self.normal, self.normal_ranges, x)

    def tangential_times(self, x: np.ndarray) -> np.ndarray:
        """T x, over T's non-zero column ranges only."""
        return _product(self.tangential, self.tangential_ranges, x)

    def both_times(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """N x and T x (x of shape (n_x,) or (n_x, cols)).

        For identical bodies T's shear block is -A where N's pressure block is A: one
        product A [p q] then reads A once where two read it twice. At 481 pairs and more
        the maps outgrow the caches and the products are memory-bound (two of them 377 us
        against 216 us for the one, cold, at 481 pairs)."""
        block = self.mirrored
        if block is None:
            return self.normal_times(x), self.tangential_times(x)
        n = self.n
        if x.ndim == 1:
            both = np.stack([x[:n], x[n : 2 * n]]) @ block.T
            normal, tangential = both[0], both[1]
        else:
            cols = x.shape[1]
            both = np.concatenate([x[:n], x[n : 2 * n]], axis=1).T @ block.T
            normal, tangential = both[:cols].T, both[cols:].T
        np.negative(tangential, out=tangential)
        rest = slice(2 * n, self.n_x)
        normal = normal + self.normal[:, rest] @ x[rest]
        tangential = tangential + self.tangential[:, rest] @ x[rest]
        return normal, tangential

    def products(self, x: np.ndarray, nonzero: np.ndarray | None = None):
        """N x, T x and R x (x of shape (n_x,) or (n_x, cols)), using only rows ``nonzero``."""
        if nonzero is not None and nonzero.size < self.n_x // 4:
            part = x[nonzero]
            return (_columns_product(self.normal, self.normal_used, nonzero, part),
                    _columns_product(self.tangential, self.tangential_used, nonzero, part),
                    self.resultant[:, nonzero] @ part)  # fmt: skip
        return (*self.both_times(x), self.resultant @ x)

    def apply(self, pattern: _Pattern, x: np.ndarray) -> tuple[np.ndarray, float]:
        """J x on ``pattern`` (every row) and the largest row product (for a relative size)."""
        n = self.n
        nx, tx, rx = self.products(x)
        out = np.empty_like(x)
        out[:n] = np.where(_column(pattern.contact, x), self.r_n * nx, x[:n])
        tangential = np.where(_column(pattern.stick, x), -self.r_t * tx, x[n : 2 * n])
        slip = pattern.slip
        tangential[slip] -= _column(pattern.coeff[slip], x) * x[:n][slip]
        out[n : 2 * n] = tangential
        out[2 * n :] = rx
        size = max(np.max(np.abs(self.r_n * nx), initial=0.0),
                   np.max(np.abs(self.r_t * tx), initial=0.0), np.max(np.abs(rx), initial=0.0),
                   np.max(np.abs(x), initial=0.0))  # fmt: skip
        return out, size

    def rows(self, pattern: _Pattern, index: np.ndarray, x: np.ndarray, dense=None):
        """Rows ``index`` (pair rows only, < 2 n) of J on ``pattern`` times x (n_x, cols).

        ``dense`` (len(index), cols), if given, holds N_i x (normal rows) or T_i x
        (tangential rows) for every index row, computed beforehand.
        """
        n = self.n
        out = np.empty((index.size, *x.shape[1:]))
        normal = index < n
        pos, pairs = normal.nonzero()[0], index[normal]
        touching = pattern.contact[pairs]
        dense_normal = self.normal[pairs[touching]] @ x if dense is None else dense[pos[touching]]
        out[pos[touching]] = self.r_n * dense_normal
        out[pos[~touching]] = x[pairs[~touching]]
        pos, pairs = (~normal).nonzero()[0], index[~normal] - n
        stick, slip = pattern.stick[pairs], pattern.slip[pairs]
        dense_stick = self.tangential[pairs[stick]] @ x if dense is None else dense[pos[stick]]
        out[pos[stick]] = -self.r_t * dense_stick
        ps = pairs[slip]
        out[pos[slip]] = x[n + ps] - _column(pattern.coeff[ps], x) * x[ps]
        sep = ~(stick | slip)
        out[pos[sep]] = x[n + pairs[sep]]
        return out


def _column(values: np.ndarray, like: np.ndarray) -> np.ndarray:
    """``values`` shaped to broadcast along the first axis of ``like``."""
    return values.reshape(-1, *([1] * (like.ndim - 1)))


class _Factor:
    """The LU of one pattern's reduced matrix; solves J y = b on that pattern for any b."""

    def __init__(self, maps: _Maps, pattern: _Pattern, previous: _Factor | None = None):
        self.maps, self.pattern = maps, pattern
        n = maps.n
        c, s = pattern.c, pattern.s
        columns = np.concatenate([c, n + s, maps.blocks])
        kc, ks = c.size, s.size
        self.size = columns.size
        self.slip_in_c = pattern.slip[c].nonzero()[0]
        slipping = c[self.slip_in_c]
        #: a slipping pair's dq follows its dp: dq_i += c_i dp_i (x numbers and c_i)
        self.slip_p, self.slip_q = slipping, n + slipping
        self.slip_coeff = pattern.coeff[slipping]
        #: the reduced rows of the stacked Jacobian (small systems; :meth:`_reduced_rows`)
        self.rows = None
        self.split = None
        if maps.normal_part is not None:
            self._factor_split(columns, slipping, previous)
        else:
            if maps.stacked is not None:
                # rows and columns of the reduced matrix are the same numbers of x: one gather
                # (C order: its transpose is the F-ordered LAPACK input); dp of a slipping pair
                # also moves its dq by c_i dp: that column folded in (the slipping pairs'
                # pressure columns, which no known value of a solve multiplies)
                rows = self.rows = maps.stacked[columns]
                if slipping.size:
                    rows[:, slipping] += rows[:, n + slipping] * self.slip_coeff
                matrix = rows[:, columns]
            else:
                matrix = self._gathered(maps, c, s, columns, slipping, self.slip_coeff)
            self.lu, self.piv = _lu(matrix)
        self.sizes = (kc, ks)
        sep = (~pattern.contact).nonzero()[0]
        self.known = np.concatenate([sep, n + sep, n + pattern.slip.nonzero()[0]])
        #: the numbers of x of the reduced unknowns (and equations), in their order
        self.reduced = columns
        self.bordered = _NO_ROWS  # rows with a kept column J^-1 e_row
        #: whether each pair row (of the 2 n) is in ``bordered``: membership by one gather,
        #: where np.isin and np.union1d sorted (about 0.15 ms a step at 481 pairs)
        self.in_border = np.zeros(2 * maps.n, dtype=bool)
        #: their columns, N or T rows and products (:meth:`border`; made on first use)
        self.columns = self.dense = self.dense_columns = None

    def _factor_split(self, columns: np.ndarray, slipping: np.ndarray, previous) -> None:
        """The block lower triangular system of uncoupled maps: the normal block (gap and
        normal block rows, whose shear columns are zero, so no slip column folds into
        them) and the tangential one with its rows' normal columns (the coupling). The
        normal block's LU is the previous factor's when the contact set is the same (the
        steps after the first of a cycle change stick and slip only). The tangential block
        is factorised when a solve first needs it (:meth:`_tangential`): a normal load
        alone leaves every shear at exactly 0 (the first step of a cycle: 3 LUs of its 17
        at 481 pairs)."""
        maps = self.maps
        normal = maps.normal_part[columns]
        a, b = normal.nonzero()[0], (~normal).nonzero()[0]
        normal_x, tangential_x = columns[a], columns[b]
        self.split = (a, b)
        self.tangential_x, self.slipping = tangential_x, slipping
        self.lu_t = self.piv_t = self.coupling = self.coupling_columns = None
        #: whether coupling @ u can be non-zero: the tangential rows see a normal column, or a
        #: slipping pair's pressure column carries its shear's
        self.coupled = bool(slipping.size) or maps.tangential_sees_normal
        self.normal_x = normal_x
        if (previous is not None and previous.split is not None
                and previous.normal_x.size == normal_x.size
                and _all(previous.normal_x == normal_x)):  # fmt: skip
            self.lu, self.piv = previous.lu, previous.piv
        else:
            self.lu, self.piv = _lu(_block(maps, normal_x, normal_x))

    def _tangential(self) -> np.ndarray:
        """The coupling (the tangential rows over the normal columns, or over
        ``coupling_columns`` of them only, where the rest are zero by structure), the
        tangential block's LU computed with it on first use."""
        if self.lu_t is None:
            maps, n = self.maps, self.maps.n
            normal_x, tangential_x, slipping = self.normal_x, self.tangential_x, self.slipping
            ka, kb = normal_x.size, tangential_x.size
            # the tangential rows over the normal columns (the coupling), their own columns
            # and the slipping pairs' shear columns, which fold into their pressure columns
            # (the first of the normal columns are the pairs in contact, c)
            coeff = self.pattern.coeff[slipping]
            if maps.tangential_sees_normal:
                rows = _block(maps, tangential_x, np.concatenate([normal_x, tangential_x,
                                                                  n + slipping]))  # fmt: skip
                coupling = rows[:, :ka]
                if slipping.size:
                    coupling[:, self.slip_in_c] += rows[:, ka + kb :] * coeff
            else:  # the normal columns are zero by structure but the slipping pairs': only
                # those are gathered and kept (coupling_columns says which)
                rows = _block(maps, tangential_x, np.concatenate([tangential_x, n + slipping]))
                coupling, ka = rows[:, kb:] * coeff, 0
                self.coupling_columns = self.slip_in_c
            self.coupling = coupling
            self.lu_t, self.piv_t = _lu(np.ascontiguousarray(rows[:, ka : ka + kb]))
        return self.coupling

    @staticmethod
    def _gathered(maps: _Maps, c, s, columns, slipping, coeff) -> np.ndarray:
        """The reduced matrix gathered from the three maps (a large system keeps no stack)."""
        k, n = columns.size, maps.n
        matrix = np.empty((k, k))  # C order: its transpose is the F-ordered LAPACK input
        kc, ks = c.size, s.size
        matrix[:kc] = _taken(maps.normal, c, columns)
        matrix[:kc] *= maps.r_n
        matrix[kc : kc + ks] = _taken(maps.tangential, s, columns)
        matrix[kc : kc + ks] *= -maps.r_t
        matrix[kc + ks :] = maps.resultant[:, columns]
        # dp of a slipping pair also moves its dq by c_i dp: fold that column in
        slip_in_c = np.arange(kc)[np.isin(c, slipping)]
        if slipping.size:
            matrix[:kc, slip_in_c] += maps.r_n * _taken(maps.normal, c, n + slipping) * coeff
            matrix[kc : kc + ks, slip_in_c] -= (
                maps.r_t * _taken(maps.tangential, s, n + slipping) * coeff
            )
            matrix[kc + ks :, slip_in_c] += maps.resultant[:, n + slipping] * coeff
        return matrix

    def _reduced_rows(self) -> np.ndarray:
        """The stacked Jacobian's rows (r_n N; -r_t T; R) of the reduced equations (small
        systems), over every column: their product with the known values is one matrix-vector
        product where the column-range products took a dozen calls."""
        if self.rows is None:
            self.rows = self.maps.stacked.take(self.reduced, axis=0)
        return self.rows

    def solve(self, b: np.ndarray) -> np.ndarray:
        """y with J y = b on this pattern (b of shape (n_x,) or (n_x, cols))."""
        maps, known = self.maps, self.known
        y = np.zeros(b.shape)
        y[known] = given = b[known]  # separated p and q; slip q's constant part
        rhs = b[self.reduced]
        if maps.stacked is not None:
            if _any(given, axis=None):
                rhs -= self._reduced_rows() @ y
        else:
            nonzero = known[_any(_flat(given), axis=1).nonzero()[0]]
            if nonzero.size:
                c, s = self.pattern.c, self.pattern.s
                nx, tx, rx = maps.products(y, nonzero)
                rhs -= np.concatenate([maps.r_n * nx[c], -maps.r_t * tx[s], rx])
        if self.split is None:
            y[self.reduced] = _lu_solve(self.lu, self.piv, rhs)
        else:
            normal, tangential = self.split
            rhs_n, rhs_t = rhs[normal], rhs[tangential]
            # a shear's unit (a bordered row of the tangential block) has none
            if _any(rhs_n, axis=None):
                y[self.normal_x] = u_n = _lu_solve(self.lu, self.piv, rhs_n)
                if self.coupled:
                    coupling = self._tangential()
                    columns = self.coupling_columns
                    rhs_t -= coupling @ (u_n if columns is None else u_n[columns])
            # else the shears are 0 (what the LU would give), not factorised
            if _any(rhs_t, axis=None):
                self._tangential()
                y[self.tangential_x] = _lu_solve(self.lu_t, self.piv_t, rhs_t)
        if self.slip_q.size:  # y at a slipping pair's p is its dp
            y[self.slip_q] += _column(self.slip_coeff, y) * y[self.slip_p]
        return y

    def border(self, rows: np.ndarray):
        """The bordered rows (``rows`` added), J^-1 e_r of each (n_x, r), their N or T rows
        (r, n_x) and those rows times the columns (r, r).

        All are computed once per row and kept; a row whose pattern row is back to this
        factor's costs nothing in the bordered solve, so every kept row stays in the border.
        """
        missing = rows[~self.in_border[rows]]
        if self.columns is None:
            n_x = self.maps.n_x
            self.columns = np.empty((n_x, 0), order="F")
            self.dense, self.dense_columns = np.empty((0, n_x)), np.empty((0, 0))
        if missing.size:
            maps, count = self.maps, self.bordered.size
            new = count + missing.size
            if new > self.columns.shape[1]:
                self._grow(2 * new)
            units = np.zeros((maps.n_x, missing.size))
            units[missing, np.arange(missing.size)] = 1.0
            self.columns[:, count:new] = self.solve(units)
            normal = missing < maps.n
            dense = self.dense[count:new]
            dense[normal] = maps.normal[missing[normal]]
            dense[~normal] = maps.tangential[missing[~normal] - maps.n]
            self.dense_columns[:count, count:new] = self.dense[:count] @ self.columns[:, count:new]
            self.dense_columns[count:new, :new] = dense @ self.columns[:, :new]
            self.bordered = np.concatenate([self.bordered, missing])
            self.in_border[missing] = True
        r = self.bordered.size
        return self.bordered, self.columns[:, :r], self.dense[:r], self.dense_columns[:r, :r]

    def border_size(self, rows: np.ndarray) -> int:
        """How many rows the border would hold with ``rows`` (distinct pair rows) added."""
        return self.bordered.size + int(np.count_nonzero(~self.in_border[rows]))

    def clear_border(self) -> None:
        """Drop the bordered rows and their columns (memory of a factor kept aside)."""
        self.bordered = _NO_ROWS
        self.in_border[:] = False
        self.columns = self.dense = self.dense_columns = None

    def _grow(self, capacity: int) -> None:
        count, n_x = self.bordered.size, self.maps.n_x
        columns = np.empty((n_x, capacity), order="F")
        dense, dense_columns = np.empty((capacity, n_x)), np.empty((capacity, capacity))
        columns[:, :count] = self.columns[:, :count]
        dense[:count] = self.dense[:count]
        dense_columns[:count, :count] = self.dense_columns[:count, :count]
        self.columns, self.dense, self.dense_columns = columns, dense, dense_columns


def _block(maps: _Maps, rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """The Jacobian's contact rows (r_n N; -r_t T; R) ``rows`` (increasing numbers of x) over
    ``columns`` (C order)."""
    if maps.stacked is not None:
        return _taken(maps.stacked, rows, columns)
    n = maps.n
    out = np.empty((rows.size, columns.size))
    k1, k2 = np.searchsorted(rows, [n, 2 * n])
    out[:k1] = _taken(maps.normal, rows[:k1], columns)
    out[:k1] *= maps.r_n
    out[k1:k2] = _taken(maps.tangential, rows[k1:k2] - n, columns)
    out[k1:k2] *= -maps.r_t
    out[k2:] = _taken(maps.resultant, rows[k2:] - 2 * n, columns)
    return out


def _taken(matrix: np.ndarray, rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """``matrix[np.ix_(rows, columns)]`` as a row take then a column take: the same numbers
    at about a third of the cost of the two-axis fancy index (C-ordered). An axis taken
    whole, in order, is not gathered (the first pattern of a cycle, every pair in contact
    and sticking: one plain copy at 481 pairs where two takes gathered 7.4 MB each, 4.5 ms).
    Always a new array (callers write it)."""
    every_row, every_column = _whole(rows, matrix.shape[0]), _whole(columns, matrix.shape[1])
    if every_row and every_column:
        return matrix.copy()
    if every_row:
        return matrix.take(columns, axis=1)
    return (
        matrix.take(rows, axis=0)
        if every_column
        else matrix.take(rows, axis=0).take(columns, axis=1)
    )


def _whole(index: np.ndarray, size: int) -> bool:
    """Whether ``index`` is 0, 1, ..., size - 1."""
    return index.size == size and bool(_all(index == np.arange(size)))


def _nonzero_ranges(matrix: np.ndarray, n: int) -> tuple[slice, ...] | None:
    """Which of the column ranges (pressures, shears, blocks) of a (., 2 n + m) map hold a
    non-zero; None if all of them (the plain product is then used)."""
    ranges = (slice(0, n), slice(n, 2 * n), slice(2 * n, matrix.shape[1]))
    kept = tuple(r for r in ranges if matrix[:, r].any())
    return None if len(kept) == len(ranges) else kept


def _used_columns(matrix: np.ndarray, ranges: tuple[slice, ...] | None) -> np.ndarray | None:
    """Whether each column lies in one of ``ranges`` (None if every column does)."""
    if ranges is None:
        return None
    used = np.zeros(matrix.shape[1], dtype=bool)
    for columns in ranges:
        used[columns] = True
    return used


def _columns_product(matrix: np.ndarray, used, columns: np.ndarray, part: np.ndarray):
    """matrix[:, columns] @ part, skipping the columns outside the matrix's non-zero ranges
    (``used``; identical bodies: the shears' columns of N, the pressures' of T)."""
    if used is not None:
        keep = used[columns]
        if not keep.all():
            if not keep.any():
                return np.zeros((matrix.shape[0], *part.shape[1:]))
            columns, part = columns[keep], part[keep]
    return matrix[:, columns] @ part


def _product(matrix: np.ndarray, ranges: tuple[slice, ...] | None, x: np.ndarray) -> np.ndarray:
    """matrix @ x over the column ``ranges`` only (all columns if None)."""
    if ranges is None:
        return matrix @ x
    if not ranges:
        return np.zeros((matrix.shape[0], *x.shape[1:]))
    out = matrix[:, ranges[0]] @ x[ranges[0]]
    for columns in ranges[1:]:
        out += matrix[:, columns] @ x[columns]
    return out


def _mirrored(normal_map: np.ndarray, tangential_map: np.ndarray) -> np.ndarray | None:
    """N's pressure block (a view) if the maps are [A 0 N_b] and [0 -A T_b], exactly (two
    identical bodies); else None."""
    n = normal_map.shape[0]
    pressure, shear = slice(0, n), slice(n, 2 * n)
    if normal_map[:, shear].any() or tangential_map[:, pressure].any():
        return None
    block = normal_map[:, pressure]
    return block if np.array_equal(block, -tangential_map[:, shear]) else None


def _lu(matrix: np.ndarray):
    """LU and pivots of a C-ordered square ``matrix`` (of its F-ordered transpose, for a
    transposed solve); LinAlgError if singular."""
    if matrix.shape[0] == 0:
        return matrix, None
    lu, piv, info = sla.lapack.dgetrf(matrix.T, overwrite_a=True)
    if info != 0:
        raise np.linalg.LinAlgError("singular reduced Newton matrix")
    return lu, piv


def _lu_solve(lu: np.ndarray, piv, rhs: np.ndarray) -> np.ndarray:
    """y with matrix y = rhs, from :func:`_lu`'s factors."""
    if rhs.shape[0] == 0:
        return rhs
    u, info = sla.lapack.dgetrs(lu, piv, rhs, trans=1)
    if info != 0:  # pragma: no cover - LAPACK argument error
        raise np.linalg.LinAlgError("reduced Newton solve failed")
    return u


def normal_part(normal_map, tangential_map, resultant_map) -> np.ndarray | None:
    """Which numbers of x belong to the normal problem when it is uncoupled, else None.

    Two bodies of identical elastic constants (Dundurs' beta = 0) uncouple the normal from
    the tangential problem: the gap does not depend on the shear. The Newton Jacobian is
    then block lower triangular (a slipping pair's shear follows its pressure, not the
    other way), so one step solves the normal block and then the tangential one: two
    factorisations of half the order, a quarter of the work, the same step. The number k
    of x names an unknown (p_i, q_i, a block's component) and its equation (gap, slip,
    a block resultant). Uncoupled means, exactly (no tolerance: a coupling at round-off is
    still a coupling, and keeps the coupled solve): the gap rows and the normal block rows
    have zeros in every shear and tangential block column. The block components are
    sorted by their columns and rows (a component whose column no slip row and whose
    resultant row no shear enters is normal).
    """
    n, n_x = normal_map.shape
    if n == 0 or resultant_map.shape[0] != n_x - 2 * n or normal_map[:, n : 2 * n].any():
        return None  # (the gap depends on the shear: a coupled problem is told at once)
    extra = np.arange(2 * n, n_x)
    column_normal = ~tangential_map[:, extra].any(axis=0)
    row_normal = ~resultant_map[:, n : 2 * n].any(axis=1)
    part = np.zeros(n_x, dtype=bool)
    part[:n] = True
    part[extra] = column_normal & row_normal
    tangential = ~part
    tangential[n : 2 * n] = False  # the gap rows' shear columns are checked above
    if normal_map[:, tangential].any() or resultant_map[part[extra]][:, ~part].any():
        return None
    return part


def _flat(values: np.ndarray) -> np.ndarray:
    """(rows, columns) view of a vector or matrix."""
    return values if values.ndim > 1 else values[:, None]


class NewtonLinear:
    """Newton steps of successive patterns, through one LU while the patterns stay close.

    The pattern's system differs from the factorised one in a few pair rows D; with
    y = J0^-1 b and Z = J0^-1 E_D (cached per row), the step is
    y - Z (J_D Z)^-1 (J_D y - b_D), exact in exact arithmetic. A residual check guards it.
    """

    def __init__(self, normal_map, tangential_map, resultant_map, friction, r_n, r_t):
        self.maps = _Maps(normal_map, tangential_map, resultant_map, r_n, r_t)
        self.friction = float(friction)
        self.factor: _Factor | None = None
        #: an earlier, larger factor kept aside (see SPARE_FRACTION), or None
        self.spare: _Factor | None = None
        self.factorisations = 0

    def matches(self, r_n: float, r_t: float, friction: float) -> bool:
        """Whether this solver was built for these augmentation parameters and friction."""
        return (self.maps.r_n, self.maps.r_t, self.friction) == (r_n, r_t, friction)

    def step(self, residual: np.ndarray, states: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """dx with J dx = -F on the pattern (states, direction); LinAlgError if singular."""
        n = self.maps.n
        pattern = _Pattern(states, direction, self.friction)
        b = -np.asarray(residual, float)
        b[n : 2 * n] += pattern.coeff * residual[:n]  # the slip rows minus c_i x normal row
        if self.factor is None:
            return self._refactor(pattern, b)
        if self.maps.n_x < DIRECT_BELOW:
            # small: factorised afresh, unless the pattern is the factorised one (the last
            # iterations of an increment) or the spare's, whose LU gives the same step
            if self.factor.pattern.same(pattern):
                return self.factor.solve(b)
            if self.spare is not None and self.spare.pattern.same(pattern):
                self._swap()
                return self.factor.solve(b)
            return self._refactor(pattern, b)
        differing = self.factor.pattern.differing_rows(pattern)
        border = self.factor.border_size(differing)
        if self.spare is not None and border:
            differing_spare = self.spare.pattern.differing_rows(pattern)
            border_spare = self.spare.border_size(differing_spare)
            if border_spare < border:
                self._swap()
                differing, border = differing_spare, border_spare
        fraction = BORDER_FRACTION if self.factor.split is None else SPLIT_BORDER_FRACTION
        if border > max(MIN_BORDER, fraction * self.factor.size):
            return self._refactor(pattern, b)
        y = self.factor.solve(b)
        if differing.size == 0:
            return y
        rows, columns, dense, dense_columns = self.factor.border(differing)
        try:
            schur = self.maps.rows(pattern, rows, columns, dense_columns)
            mismatch = self.maps.rows(pattern, rows, y, dense @ y) - b[rows]
            dx = _exact_rows(pattern, b, _bordered(schur, columns, mismatch, y))
            for refinement in range(2):  # accept, refine once, or refactorise
                applied, size = self.maps.apply(pattern, dx)
                defect = b - applied
                if np.max(np.abs(defect)) <= ACCEPT_RESIDUAL * max(size, np.max(np.abs(b))):
                    return dx
                if refinement == 0:
                    y = self.factor.solve(defect)
                    mismatch = self.maps.rows(pattern, rows, y, dense @ y) - defect[rows]
                    dx = _exact_rows(pattern, b, dx + _bordered(schur, columns, mismatch, y))
        except np.linalg.LinAlgError:
            pass
        return self._refactor(pattern, b)

    def _refactor(self, pattern: _Pattern, b: np.ndarray) -> np.ndarray:
        previous, self.factor, self.spare = self.factor, None, None
        if self.maps.normal_part is None and not self._keeps(previous, pattern):
            previous = None  # free the old LU first
        self.factor = _Factor(self.maps, pattern, previous)
        if self._keeps(previous, pattern):
            self.spare = previous
            previous.clear_border()
        del previous
        self.factorisations += 1
        return self.factor.solve(b)

    def _keeps(self, previous: _Factor | None, pattern: _Pattern) -> bool:
        """Whether ``previous`` is kept aside when ``pattern`` is factorised (SPARE_FRACTION
        of its order at most: the two LUs then take little more memory than it alone)."""
        if previous is None:
            return False
        size = pattern.c.size + pattern.s.size + self.maps.blocks.size
        return size <= SPARE_FRACTION * previous.size

    def _swap(self) -> None:
        """The spare becomes the factor and the factor the spare (its border dropped)."""
        self.factor, self.spare = self.spare, self.factor
        self.spare.clear_border()


def _exact_rows(pattern: _Pattern, b: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """dx with the pattern's identity rows solved exactly, as the reduced solve does: a
    separated pair's p and q land on exactly 0, a slipping pair's q on exactly c_i p."""
    n = pattern.states.size
    separated = (~pattern.contact).nonzero()[0]
    slipping = pattern.slip.nonzero()[0]
    dx[separated] = b[separated]
    dx[n + separated] = b[n + separated]
    dx[n + slipping] = b[n + slipping] + pattern.coeff[slipping] * dx[slipping]
    return dx


def _bordered(schur: np.ndarray, columns: np.ndarray, mismatch: np.ndarray, y: np.ndarray):
    """y - Z S^-1 (J_D y - b_D): the solve on the factorised pattern, corrected on D."""
    return y - columns @ np.linalg.solve(schur, mismatch)


def reduced_newton_step(
    normal_map: np.ndarray,
    tangential_map: np.ndarray,
    resultant_map: np.ndarray,
    residual: np.ndarray,
    states: np.ndarray,
    direction: np.ndarray,
    friction: float,
    r_n: float,
    r_t: float,
) -> np.ndarray:
    """The Newton step dx solving J dx = -F, from the active rows of J only.

    Parameters
    ----------
    normal_map, tangential_map : ndarray, shape (n, n_x)
        Relative normal and tangential displacement per unit of x.
    resultant_map : ndarray, shape (m, n_x)
        Block resultant forces per unit of x (n_x = 2 n + m).
    residual : ndarray, shape (n_x,)
        F = (F_n, F_t, F_b) at the current iterate.
    states : ndarray of int, shape (n,)
        SEPARATED (0), STICK (1) or SLIP (2) of every pair.
    direction : ndarray, shape (n,)
        Sign of the trial tangential traction (used on slipping pairs).
    friction, r_n, r_t : float
        Coulomb coefficient and the normal and tangential augmentation parameters.

    Raises
    ------
    numpy.linalg.LinAlgError
        If the reduced matrix is singular (then so is the full Jacobian).
    """
    linear = NewtonLinear(normal_map, tangential_map, resultant_map, friction, r_n, r_t)
    return linear.step(residual, states, direction)
