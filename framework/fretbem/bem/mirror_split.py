"""The collocation system of a body symmetric about the y axis, solved as two half systems.

The reflection P: (x, y) -> (-x, y) of the unknowns (function b's component k to its mirror
Q(b)'s, times s_k, s = (-1, 1)) commutes with H and G of a mirror-symmetric body
(:mod:`fretbem.bem.mirror`), and with the collocation matrix A when the boundary conditions
are symmetric too. A then maps the even unknowns (P x = x) and the odd ones (P x = -x) to
themselves: in the basis w_c = e_c +- s_c e_Q(c) of one representative dof c per mirrored
pair (2 e_c for a dof that is its own mirror and of that parity) A is block diagonal, two
blocks of half size, ``A± = A[D, D] ± A[D, Q(D)] s`` (columns). Two half LUs cost a quarter
of the full one's flops and each right-hand side half of its solves; a contact column's
even and odd combinations with its mirror column fall in one half each, so the contact
face's columns cost a quarter too. The change of basis is orthogonal up to powers of two
and the rows of A it drops are the mirrors of the rows it keeps (checked, to
:data:`ROUNDING`), so the unknowns equal the full solve's to round-off.
"""

from __future__ import annotations

import sys

import attrs
import numpy as np
import scipy.linalg as sla

#: how far a mirrored row of H or G may differ from its mirror's, relative to the matrix's
#: largest entry (the assembly fills the mirrored rows from the integrated ones, which are
#: symmetric to round-off: measured at most 1.8e-14 for H and 3.5e-14 for G, the reference
#: bodies at 61 and 481 pairs, nurbs and lagrange2)
ROUNDING = 2.0**-40
#: bodies of fewer rows are solved whole: building and checking the halves costs about what
#: they save below it (the reference pad's system, A kept for its image: 0.9x at 278 rows,
#: 1.03x at 638, 1.47x at 1,118; ``benchmarks/mirror_split.py --keep``)
MIN_ROWS = 800
#: rows gathered at once by the check and the half matrices' construction (its buffers, about
#: 5 CHUNK rows of H: 5.7 MB at 1,118 rows). In the 481-pair cycle, one process, cold scenes
#: alternating, medians of 15 (load 7): the build 38.2 ms at 256, 13.0 ms at 128 (9 more
#: alternating: 21.6 at 256, 14.2 at 128, 14.9 at 64); the same numbers (elementwise work)
CHUNK = 128
#: the module of the compiled assembly loops: once numba has loaded it, :func:`build` runs
#: as one compiled pass (:mod:`fretbem.bem.compiled_split`)
_COMPILED = "fretbem.bem.compiled_loops"
SIGNS = np.array([-1.0, 1.0])

#: an index array gathered by slices when it falls into at most this fraction of its length
#: in arithmetic pieces (a mirror reverses whole segments: a few pieces per component)
PIECES_FRACTION = 1 / 16


class Index:
    """An index array along one axis, gathered and scattered by strided slices (its
    arithmetic pieces, found once; in two interleaved halves when a dof's x and y
    alternate), or by fancy indexing when it has too many pieces."""

    def __init__(self, index: np.ndarray):
        self.index = np.asarray(index, dtype=np.intp)
        self.pieces = _pieces(self.index, 0, 1)
        if self.pieces is None:
            even, odd = _pieces(self.index[0::2], 0, 2), _pieces(self.index[1::2], 1, 2)
            self.pieces = None if even is None or odd is None else even + odd

    def __len__(self) -> int:
        return len(self.index)

    def _views(self, array: np.ndarray, axis: int):
        """(positions, values) slices of each piece: where in the gathered axis, where in
        ``array``'s."""
        for start, step, count, first, stride in self.pieces:
            where = slice(start, start + step * (count - 1) + 1, step)
            what = slice(first, None if first + stride * count < 0 else first + stride * count,
                         stride)  # fmt: skip
            yield (where, what) if axis == 0 else ((slice(None), where), (slice(None), what))

    def take(self, array: np.ndarray, axis: int, out: np.ndarray) -> np.ndarray:
        """out = array[index] along ``axis`` (0 or 1)."""
        if self.pieces is None:
            return np.take(array, self.index, axis=axis, out=out)
        for where, what in self._views(array, axis):
            out[where] = array[what]
        return out

    def put(self, array: np.ndarray, values: np.ndarray, axis: int) -> None:
        """array[index] = values along ``axis`` (0 or 1)."""
        if self.pieces is None:
            if axis == 0:
                array[self.index] = values
            else:
                array[:, self.index] = values
            return
        for where, what in self._views(array, axis):
            array[what] = values[where]


def _pieces(values: np.ndarray, start: int, step: int) -> list | None:
    """(position, position step, count, first value, value step) of the arithmetic pieces of
    ``values`` (at positions start, start + step, ...), greedily; None if there are more
    than :data:`PIECES_FRACTION` of its length (and more than 4)."""
    n = len(values)
    if n == 0:
        return []
    limit = max(4, int(PIECES_FRACTION * n))
    d = np.diff(values)
    run = np.concatenate([[0], np.cumsum(d[1:] != d[:-1])]) if d.size else np.zeros(0, int)
    last = np.zeros(run.max(initial=-1) + 1, dtype=np.intp)
    last[run] = np.arange(len(d))  # the last position in d of each run of equal steps
    out, i = [], 0
    while i < n:
        if len(out) >= limit:
            return None
        if i == n - 1 or d[i] == 0:
            out.append((start + step * i, step, 1, int(values[i]), 1))
            i += 1
            continue
        stop = int(last[run[i]]) + 2
        out.append((start + step * i, step, stop - i, int(values[i]), int(d[i])))
        i = stop
    return out


@attrs.frozen(eq=False)
class Halves:
    """The dofs of the even (``parity`` +1) or odd (-1) half system: ``dofs`` (its rows and
    unknowns, in A's numbering: the representatives of mirrored pairs, then the dofs that
    are their own mirror and of this parity), their mirrors and the signs t = parity s."""

    parity: int
    dofs: np.ndarray
    mirrors: np.ndarray
    signs: np.ndarray
    pairs: int  # the first ``pairs`` dofs represent a mirrored pair, the rest are their own
    take_dofs: Index = attrs.field(init=False)
    take_mirrors: Index = attrs.field(init=False)

    def __attrs_post_init__(self) -> None:
        object.__setattr__(self, "take_dofs", Index(self.dofs))
        object.__setattr__(self, "take_mirrors", Index(self.mirrors))


@attrs.frozen(eq=False)
class MirrorSplit:
    """The mirror of every dof (``mirror``), its sign (``sign``: s_k), and both halves."""

    mirror: np.ndarray
    sign: np.ndarray
    even: Halves
    odd: Halves
    take_mirror: Index = attrs.field(init=False)
    pair_rows: Index = attrs.field(init=False)  # the pairs' representatives
    pair_mirror_rows: Index = attrs.field(init=False)  # and their mirrors

    def __attrs_post_init__(self) -> None:
        p = self.even.pairs
        object.__setattr__(self, "take_mirror", Index(self.mirror))
        object.__setattr__(self, "pair_rows", Index(self.even.dofs[:p]))
        object.__setattr__(self, "pair_mirror_rows", Index(self.even.mirrors[:p]))

    @classmethod
    def of(cls, q: np.ndarray, representative: np.ndarray) -> MirrorSplit:
        """From the functions' mirror Q and whether each function represents its pair
        (:func:`fretbem.bem.mirror.integrated_rows`: the same choice for rows and columns)."""
        n = len(q)
        mirror = (2 * q[:, None] + np.arange(2)).ravel()
        sign = np.tile(SIGNS, n)
        own = np.flatnonzero(q == np.arange(n))
        reps = np.flatnonzero(representative & (q != np.arange(n)))
        pair_dofs = (2 * reps[:, None] + np.arange(2)).ravel()
        halves = []
        for parity, component in ((1, 1), (-1, 0)):
            dofs = np.concatenate([pair_dofs, 2 * own + component])
            halves.append(Halves(parity, dofs, mirror[dofs], parity * sign[dofs], len(pair_dofs)))
        return cls(mirror, sign, *halves)

    def symmetric_kinds(self, kinds: np.ndarray) -> bool:
        """Whether every dof's mirror is of its kind (the conditions are symmetric)."""
        return bool(np.array_equal(kinds[self.mirror], kinds))


@attrs.frozen(eq=False)
class HalfSystems:
    """Both halves' matrices ``A±`` (F-ordered) and contact right-hand sides ``G±`` (the
    columns of the contact dofs in the half, at positions ``contact_at`` of its dofs)."""

    matrices: tuple[np.ndarray, np.ndarray]
    contact: tuple[np.ndarray, np.ndarray]
    contact_at: tuple[np.ndarray, np.ndarray]


def build(split: MirrorSplit, h, g, solves_u, contact) -> HalfSystems | None:
    """``A± = A[D, D] + t A[D, Q(D)]`` and ``G± = G[D, C] + t G[D, Q(C)]``, A = H with the
    columns of traction unknowns from -G, read row chunk by row chunk from H and G; None
    unless H and G are mirror-symmetric, M[Q(i), Q(j)] s_i s_j = M[i, j] to
    :data:`ROUNDING` of each one's largest entry, on every row the halves keep (a pair's
    representative against its mirror, an own-mirror row against itself): the rows the
    halves drop are then the kept ones' mirrors."""
    p = split.even.pairs
    halves = (split.even, split.odd)
    contact_at = tuple(np.flatnonzero(np.isin(half.dofs, contact)) for half in halves)
    matrices = tuple(np.empty((len(half.dofs),) * 2, order="F") for half in halves)
    rhs = tuple(
        np.empty((len(half.dofs), len(at)), order="F")
        for half, at in zip(halves, contact_at, strict=True)
    )
    negate = np.flatnonzero(~np.asarray(solves_u))
    worst, scale = np.zeros(2), np.zeros(2)
    groups = ((split.even.dofs[:p], (0, 1), 0), (split.even.dofs[p:], (0,), p),
              (split.odd.dofs[p:], (1,), p))  # fmt: skip
    if _COMPILED in sys.modules and _compiled_build(
        split, h, g, solves_u, groups, matrices, rhs, contact_at, worst, scale
    ):
        if np.any(worst > ROUNDING * scale):
            return None
        return HalfSystems(matrices, rhs, contact_at)
    n = len(split.mirror)
    # buffers reused by every chunk (fresh arrays of a few MB each cost page faults)
    kept = np.empty((2, CHUNK, n))
    mirrored, other = np.empty((CHUNK, n)), np.empty((CHUNK, n))
    widest = max(len(half.dofs) for half in halves)
    block, second = np.empty((CHUNK, widest)), np.empty((CHUNK, widest))
    columns = [
        ((half.take_dofs, half.take_mirrors, half.signs, matrices[k]),
         (Index(half.dofs[contact_at[k]]), Index(half.mirrors[contact_at[k]]),
          half.signs[contact_at[k]], rhs[k]))
        for k, half in enumerate(halves)
    ]  # fmt: skip
    for group, which, first in groups:
        for start in range(0, len(group), CHUNK):
            rows = group[start : start + CHUNK]
            m = len(rows)
            own_rows, mirror_rows = Index(rows), Index(split.mirror[rows])
            for k, matrix in enumerate((h, g)):
                own_rows.take(matrix, 0, kept[k, :m])
                mirror_rows.take(matrix, 0, mirrored[:m])
                split.take_mirror.take(mirrored[:m], 1, other[:m])
                other[:m] *= split.sign[rows, None]
                other[:m] *= split.sign
                other[:m] -= kept[k, :m]
                worst[k] = max(worst[k], np.abs(other[:m]).max(initial=0.0))
                scale[k] = max(scale[k], np.abs(kept[k, :m]).max(initial=0.0))
            a_rows, g_rows = kept[0, :m], kept[1, :m]
            a_rows[:, negate] = -g_rows[:, negate]
            target = slice(first + start, first + start + m)
            for k in which:
                for source, (dofs, mirrors, signs, out) in zip(
                    (a_rows, g_rows), columns[k], strict=True
                ):
                    here, added = block[:m, : len(dofs)], second[:m, : len(dofs)]
                    mirrors.take(source, 1, here)
                    here *= signs
                    here += dofs.take(source, 1, added)
                    out[target] = here
    if np.any(worst > ROUNDING * scale):
        return None
    return HalfSystems(matrices, rhs, contact_at)


def _compiled_build(split, h, g, solves_u, groups, matrices, rhs, contact_at, worst, scale):
    """:func:`build`'s loop as one compiled pass (:mod:`fretbem.bem.compiled_split`, the
    same numbers), for C-ordered float H and G; False (nothing done) otherwise."""
    if not (h.flags.c_contiguous and g.flags.c_contiguous and h.dtype == g.dtype == np.float64):
        return False
    from . import compiled_split

    rows = np.concatenate([group for group, _, _ in groups])
    which = np.concatenate([np.full(len(group), 2 if len(halves) == 2 else halves[0])
                            for group, halves, _ in groups])  # fmt: skip
    targets = np.concatenate([first + np.arange(len(group)) for group, _, first in groups])
    halves = tuple(
        (half.dofs, half.mirrors, half.signs, matrices[k], half.dofs[contact_at[k]],
         half.mirrors[contact_at[k]], half.signs[contact_at[k]], rhs[k])
        for k, half in enumerate((split.even, split.odd))
    )  # fmt: skip
    compiled_split.build_rows(
        h, g, rows.astype(np.intp), which.astype(np.intp), targets.astype(np.intp),
        split.mirror, split.sign, np.asarray(solves_u, dtype=np.bool_), halves, worst, scale,
    )  # fmt: skip
    return True


def project(half: Halves, columns: np.ndarray) -> np.ndarray:
    """The half system's right-hand sides of full ones: (b[D] + t b[Q(D)]) / 2, F-ordered."""
    out = np.asfortranarray(columns[half.mirrors])
    out *= half.signs[:, None]
    out += columns[half.dofs]
    out *= 0.5
    return out


def expanded(split: MirrorSplit, even, odd, out: np.ndarray, scale: float = 1.0) -> None:
    """``out = scale (W+ y+ + W- y-)`` on every row, W the halves' bases (None: y = 0): on
    a pair's representative ``y+ + y-``, on its mirror ``s (y+ - y-)``, on an own dof 2 y."""
    p = split.even.pairs
    for half, y in ((split.even, even), (split.odd, odd)):
        if y is None:
            out[half.dofs[p:]] = 0.0
        else:
            out[half.dofs[p:]] = (2.0 * scale) * y[p:]
    sign = split.sign[split.even.dofs[:p], None]
    if even is None or odd is None:
        pair = even[:p] if odd is None else odd[:p]
        parity = 1.0 if odd is None else -1.0
        split.pair_rows.put(out, scale * pair, 0)
        split.pair_mirror_rows.put(out, (parity * scale) * sign * pair, 0)
        return
    _combined(split.pair_rows, np.add, even[:p], odd[:p], scale, out)
    _combined(split.pair_mirror_rows, np.subtract, even[:p], odd[:p], scale * sign, out)


def _combined(rows: Index, operation, a, b, factor, out: np.ndarray) -> None:
    """``out[rows] = operation(a, b) * factor`` (``factor`` a number or one per row),
    computed into ``out``'s rows piece by piece where ``rows`` are strided slices (no
    temporary: a fresh one of a chunk's size cost its page faults every time)."""
    if rows.pieces is None:
        total = operation(a, b)
        total *= factor
        rows.put(out, total, 0)
        return
    for where, what in rows._views(out, 0):
        target = out[what]
        operation(a[where], b[where], out=target)
        target *= factor if np.ndim(factor) == 0 else factor[where]


class SplitFactor:
    """The LU factors of both halves (``failed`` if either is singular); solves A x = b."""

    def __init__(self, split: MirrorSplit, systems: HalfSystems):
        self.split = split
        self.systems = systems
        self.factors = []
        self.failed = False
        for matrix in systems.matrices:
            lu, piv, info = sla.lapack.dgetrf(matrix, overwrite_a=True)
            self.failed |= info != 0
            self.factors.append((lu, piv))

    def solve_half(self, which: int, rhs: np.ndarray) -> np.ndarray:
        """A half's solution for its right-hand sides (in place when F-ordered)."""
        lu, piv = self.factors[which]
        out, info = sla.lapack.dgetrs(lu, piv, rhs, overwrite_b=True)
        if info != 0:
            self.failed = True
        return out

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """A^-1 rhs for full right-hand sides (n, m)."""
        out = np.empty(rhs.shape)
        if rhs.shape[1]:
            even = self.solve_half(0, project(self.split.even, rhs))
            odd = self.solve_half(1, project(self.split.odd, rhs))
            expanded(self.split, even, odd, out)
        return out

    def solve_contact(self, contact: np.ndarray, out: np.ndarray) -> None:
        """A^-1 G[:, contact] into ``out`` (n, len(contact)), ``contact`` (closed under the
        mirror) the dofs :func:`build` was given: each half solves the even or odd
        combinations of mirrored columns, a quarter of the full solve's work. The
        halves' right-hand sides are solved in place and released."""
        column = {int(c): k for k, c in enumerate(contact)}
        solved = []
        for which in range(2):
            rhs, where = self.systems.contact[which], self.systems.contact_at[which]
            solved.append((self.solve_half(which, rhs), where))
        self.systems = None
        (even, even_at), (odd, _) = solved
        p = self.split.even.pairs
        reps = even_at[even_at < p]  # the pair representatives on the face: in both halves
        dofs = self.split.even.dofs[reps]
        targets = np.array([column[int(d)] for d in dofs], dtype=np.intp)
        mirrored = np.array([column[int(d)] for d in self.split.mirror[dofs]], dtype=np.intp)
        sign = self.split.sign[dofs]
        n = len(out)
        # F-ordered like ``out`` and the halves' solutions: every copy runs down columns
        # (a C-ordered buffer made each of them a transpose, ~12 s at 3,841 pairs)
        buffer = np.empty((n, min(CHUNK, len(reps))), order="F")
        for start in range(0, len(reps), CHUNK):
            cut = slice(start, min(start + CHUNK, len(reps)))
            e, o = even[:, cut], odd[:, cut]
            _expanded_columns(self.split, e, o, out, Index(targets[cut]), buffer)
            np.negative(o, out=o)
            _expanded_columns(self.split, e, o, out, Index(mirrored[cut]), buffer, sign[cut])
        for which, (y, at) in enumerate(solved):
            own = np.flatnonzero(at >= p)
            if not own.size:
                continue
            half = (self.split.even, self.split.odd)[which]
            buffer = np.empty((n, len(own)))
            pair = (y[:, own], None) if which == 0 else (None, y[:, own])
            expanded(self.split, *pair, buffer, 0.5)
            out[:, [column[int(d)] for d in half.dofs[at[own]]]] = buffer


def _expanded_columns(split, even, odd, out, columns: Index, buffer, sign=None) -> None:
    """``out[:, columns] = sign 0.5 (W+ even + W- odd)`` (:func:`expanded`'s numbers):
    straight into ``out``'s columns, piece by piece, when ``columns`` are strided slices of
    an F-ordered ``out``, else through ``buffer`` (F-ordered, at least as wide)."""
    if columns.pieces is not None and out.strides[0] == out.itemsize:
        for where, what in columns._views(out, 1):
            here = out[what]
            expanded(split, even[where], odd[where], here, 0.5)
            if sign is not None:
                here *= sign[where[1]]
        return
    here = buffer[:, : even.shape[1]]
    expanded(split, even, odd, here, 0.5)
    if sign is not None:
        here *= sign
    columns.put(out, here, 1)
