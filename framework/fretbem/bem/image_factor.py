"""One factorisation for a body and its point image (the reference scene's pad and specimen).

A body whose every segment is the exact point image of a segment of the body factorised
just before (:mod:`fretbem.bem.images`: the same H and G blocks) and whose boundary
conditions correspond (the pad's loading block and the specimen's clamped bottom both leave
the traction unknown) has that body's collocation matrix with its rows and columns permuted
segment by segment, to round-off: the rigid-body terms on the diagonal are row sums in
another order, and the other blocks are equal to the last bit when the image took the other
body's blocks, to round-off when the compiled loops integrated it again. Its system is then
solved with the kept LU factors, and the parameter columns equal to the kept body's to the
same round-off (the contact columns: G's columns on the contact face) take its solved
columns. The
correspondence is checked block by block; anything else is factorised as before. A body
whose H and G are the kept body's permuted (:mod:`fretbem.bem.image_matrices`) needs no
block check: its matrix is the kept one permuted, exactly, when its unknowns' kinds (u or t
solved) correspond, which is all that is checked, and its matrix is never built. Only the
last factorisation is kept, and only a small one.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable

import attrs
import numpy as np

#: the largest collocation matrix whose factorisation is kept for a point image (rows): the
#: kept matrix, its LU factors and its parameter columns, about 100 MB at this size
KEEP_MAX_ROWS = 2048
#: how far a block may differ from its image's, relative to the block's largest entry: the
#: rigid-body terms on the diagonal are row sums taken in the body's segment order, which
#: differs between the two bodies (measured 4e-16 absolute on entries about 1); the compiled
#: loops (a body too large to share its blocks) integrate an image to round-off, not to the
#: last bit (measured 2.8e-17 absolute on entries about 1e-2 at 481 pairs)
ROUNDING = 2.0**-40


@attrs.frozen(eq=False)
class KeptFactor:
    """The last small factorisation: its system (weak: the object that asked for it), its
    body's segments (weak), their first dofs and first rows, the matrix (None where the
    mirror split's halves solved it without building it), the solve with its
    factors (A^-1 b, None if singular: an LU or the mirror split's halves), the parameter
    columns (:class:`LazyParameters` where only the general ones are held) and their
    solution; whether each unknown is a displacement (H's column in the matrix, else -G's)
    and the H the matrix was built from (weak; None: not known)."""

    owner: weakref.ref
    segments: tuple
    first_dofs: np.ndarray
    first_rows: np.ndarray
    matrix: np.ndarray | None
    solve: Callable[[np.ndarray], np.ndarray | None]
    parameters: np.ndarray | LazyParameters
    solution: np.ndarray
    solves_u: np.ndarray | None = None
    h: weakref.ref | None = None


_KEPT: list[KeptFactor | None] = [None]


class LazyParameters:
    """A kept body's parameter columns [z0, block, contact, load columns] of which only the
    general ones are held, the contact ones (G's on the contact dofs) taken from G when
    first asked for (:meth:`full`): the halves of a mirror-split body never form them, and
    its point image served by :func:`solve_permuted` never asks."""

    def __init__(self, general: np.ndarray, g: np.ndarray, contact_dofs: np.ndarray):
        self.general, self.g, self.contact_dofs = general, g, contact_dofs
        self.shape = (len(general), general.shape[1] + len(contact_dofs))

    def full(self) -> np.ndarray:
        """The columns in order, F-ordered: the numbers the body's own parameters hold
        (:func:`fretbem.bem.system.collocation_parameters`)."""
        contacts = len(self.contact_dofs)
        out = np.empty(self.shape, order="F")
        out[:, :3] = self.general[:, :3]
        out[:, 3 : 3 + contacts] = self.g[:, self.contact_dofs]
        out[:, 3 + contacts :] = self.general[:, 3:]
        return out


def _full(parameters) -> np.ndarray:
    """A kept factorisation's parameter columns, formed where they are kept lazily."""
    return parameters.full() if isinstance(parameters, LazyParameters) else parameters


def _general(parameters, where: np.ndarray) -> np.ndarray:
    """A kept factorisation's general parameter columns (``where``: their numbers)."""
    if isinstance(parameters, LazyParameters):
        return parameters.general
    return parameters[:, where]


def clear() -> None:
    """Forget the kept factorisation."""
    _KEPT[0] = None


def keep(
    owner, segments, first_dofs, first_rows, matrix, solve, parameters, solution,
    solves_u=None, h=None,
) -> None:  # fmt: skip
    """Keep a factorisation (copies of the matrix and the parameters, taken before LAPACK
    overwrote them) for the next body, if it is small enough; else forget the last one.
    ``solves_u`` and ``h``: the unknowns' kinds and the H the matrix was built from, for a
    body whose H and G are this one's permuted."""
    if parameters.shape[0] > KEEP_MAX_ROWS:
        clear()
        return
    refs = tuple(weakref.ref(basis) for basis in segments)
    _KEPT[0] = KeptFactor(
        weakref.ref(owner), refs, first_dofs, first_rows, matrix, solve, parameters, solution,
        solves_u, None if h is None else weakref.ref(h),
    )  # fmt: skip


def may_serve(segments, first_dofs, first_rows, image_of) -> bool:
    """Whether the kept factorisation may serve a body of these segments: each the point
    image of one of its body's (its matrix then to be compared)."""
    kept = _KEPT[0]
    return (
        kept is not None
        and kept.matrix is not None
        and segment_map(kept, segments, first_dofs, first_rows, image_of) is not None
    )


def solve_as_image(
    segments, first_dofs, first_rows, image_of, matrix, parameters, *,
    solves_u=None, permuted_from=None,
) -> tuple | None:  # fmt: skip
    """(A^-1 parameters, the kept factorisation's owner or None if it is gone) from the kept
    factorisation when A is the kept matrix permuted segment by segment (``image_of(basis)``:
    the segment ``basis`` is the point image of), checked; None otherwise. The kept
    factorisation serves once; where it serves, the solution overwrites ``parameters``
    (F-ordered) and is returned.

    ``permuted_from``: the H whose rows and columns, permuted segment by segment as
    ``image_of`` maps them, are this body's H (and the same for G:
    :func:`fretbem.bem.image_matrices.derived`); when the kept matrix was built from it,
    only the kinds ``solves_u`` are compared with the kept ones, and ``matrix`` may be None.
    """
    kept = _KEPT[0]
    if kept is None or kept.first_rows[-1] != len(parameters):
        return None
    mapped = segment_map(kept, segments, first_dofs, first_rows, image_of)
    if mapped is None:
        return None
    columns, rows, _ = mapped
    permuted = (
        permuted_from is not None
        and kept.h is not None
        and kept.h() is permuted_from
        and kept.solves_u is not None
        and solves_u is not None
    )
    if permuted:  # A is the kept one permuted when each column is H's or -G's alike
        for own, other in columns:
            if not np.array_equal(solves_u[own], kept.solves_u[other]):
                return None
    elif matrix is None or kept.matrix is None:
        return None
    else:
        for own_rows, kept_rows in rows:
            for own, other in columns:
                if not _close(matrix[own_rows, own], kept.matrix[kept_rows, other]):
                    return None
    # the parameter columns equal to the kept ones (to round-off) take the kept solution;
    # the others are solved with the kept factors: rows and unknowns permuted segment by
    # segment, by slices
    same = np.zeros(parameters.shape[1], bool)
    if kept.parameters.shape == parameters.shape:  # columns solved already
        same = _same_columns(parameters, _full(kept.parameters), rows)
    found = _kept_solve(kept, parameters, same, rows)
    if found is None:
        return None
    rest, solved = found
    clear()
    # the solution goes into the parameters' buffer (read for the last time above): a fresh
    # face-sized array's first writes cost page faults, 2-17 ms at 481 pairs on a busy machine
    result = parameters if parameters.flags.f_contiguous else np.empty(parameters.shape, "F")
    for own, other in columns:
        result[own] = kept.solution[other]
        if solved is not None:
            result[own, rest] = solved[other]
    return result, kept.owner()


def solve_permuted(
    segments, first_dofs, first_rows, image_of, general, contact_dofs, column_map, *,
    solves_u, permuted_from,
) -> tuple | None:  # fmt: skip
    """:func:`solve_as_image` for a body whose H and G are the kept body's permuted and are
    never formed: from its general parameter columns [z0, block columns, load columns]
    alone. Its contact columns (G's on its contact dofs) are then the kept body's contact
    columns, rows permuted, exactly, when ``column_map`` (the kept dof of each own dof)
    takes its contact dofs to the kept body's in order: their solution is the kept one's.
    The same numbers as :func:`solve_as_image` (whose comparison finds those columns equal
    to the last bit); None where it would not serve, or where the contact dofs do not
    correspond so.

    Returns (the general columns' solution, its contact columns' as :class:`PermutedRows`,
    the kept factorisation's owner): the contact columns are the kept solution's rows
    permuted, formed only if asked for (a run never asks: its contact response takes the
    kept body's; 481 pairs, an 8.6 MB copy, 3-7 ms, fewer)."""
    kept = _KEPT[0]
    owner = None if kept is None else kept.owner()
    if (
        owner is None
        or kept.first_rows[-1] != len(general)
        or kept.h is None
        or kept.h() is not permuted_from
        or kept.solves_u is None
    ):
        return None
    kept_contact = getattr(owner, "contact_dofs", None)
    contacts = len(contact_dofs)
    if (
        kept_contact is None
        or len(kept_contact) != contacts
        or kept.parameters.shape != (len(general), general.shape[1] + contacts)
        or not np.array_equal(column_map[contact_dofs], kept_contact)
    ):
        return None
    mapped = segment_map(kept, segments, first_dofs, first_rows, image_of)
    if mapped is None:
        return None
    columns, rows, _ = mapped
    for own, other in columns:
        if not np.array_equal(solves_u[own], kept.solves_u[other]):
            return None
    # the general columns of the parameters: [z0, block x, block y] first, loads last
    where = np.r_[0:3, 3 + contacts : kept.parameters.shape[1]]
    same = _same_columns(general, _general(kept.parameters, where), rows)
    found = _kept_solve(kept, general, same, rows)
    if found is None:
        return None
    rest, solved = found
    clear()
    result = np.empty(general.shape, order="F")
    for own, other in columns:
        result[own] = kept.solution[other][:, where]
        if solved is not None:
            result[own, rest] = solved[other]
    contact = PermutedRows(kept.solution[:, 3 : 3 + contacts], columns)
    return result, contact, owner


class PermutedRows:
    """A kept solution's columns with their rows permuted segment by segment (``columns``:
    own and kept slices), formed on first call: the numbers :func:`solve_permuted` would
    copy."""

    def __init__(self, kept: np.ndarray, columns: list):
        self.kept, self.columns = kept, columns

    def __call__(self) -> np.ndarray:
        out = np.empty(self.kept.shape, order="F")
        for own, other in self.columns:
            out[own] = self.kept[other]
        return out


def _kept_solve(kept, parameters: np.ndarray, same: np.ndarray, rows) -> tuple | None:
    """(the columns ``rest`` of ``parameters`` not ``same`` as the kept ones, the kept
    factors' solution of them or None if there are none), their rows permuted segment by
    segment into the kept body's order (``rows``: own and kept row slices); None where the
    kept factors are gone."""
    rest = np.flatnonzero(~same)
    if not rest.size:
        return rest, None
    permuted = np.empty((len(parameters), rest.size), order="F")  # [kept row, column]
    for own, other in rows:
        permuted[other] = parameters[own][:, rest]
    solved = kept.solve(permuted)
    return None if solved is None else (rest, solved)


def _close(block: np.ndarray, kept: np.ndarray) -> bool:
    """Whether ``block`` equals ``kept`` to :data:`ROUNDING` of kept's largest entry. Only
    the entries that differ are differenced: a diagonal block differs in its rigid-body
    terms alone (lent blocks; a body integrated again differs in most entries, then
    all are differenced)."""
    differ = block != kept
    count = np.count_nonzero(differ)
    if not count:
        return True
    scale = max(kept.max(), -kept.min())
    if count > differ.size // 8:  # integrated again, not lent: most entries differ
        return bool(np.all(np.abs(block - kept) <= ROUNDING * scale))
    return bool(np.all(np.abs(block[differ] - kept[differ]) <= ROUNDING * scale))


def _same_columns(parameters: np.ndarray, kept: np.ndarray, rows) -> np.ndarray:
    """Whether each parameter column equals the kept one (rows mapped segment by segment)
    to :data:`ROUNDING` of the kept column's largest entry. Columns equal to the last bit
    (the image's contact columns of G, from the lent blocks: all but a few) are told by
    one comparison; only the others are differenced (481 pairs: 965 columns, 2 differ), or
    all where most differ (a body integrated again)."""
    equal = np.ones(parameters.shape[1], bool)
    for own, other in rows:
        equal &= (parameters[own] == kept[other]).all(axis=0)
    if equal.all():
        return equal
    differ = np.flatnonzero(~equal)
    worst = np.zeros(differ.size)
    if differ.size > equal.size // 8:  # integrated again, not lent: most columns differ
        differ, worst = slice(None), np.zeros(equal.size)
    for own, other in rows:
        difference = parameters[own][:, differ] - kept[other][:, differ]
        np.maximum(worst, np.abs(difference).max(axis=0, initial=0.0), out=worst)
    equal[differ] = worst <= ROUNDING * np.abs(kept[:, differ]).max(axis=0, initial=0.0)
    return equal


def segment_map(kept, segments, first_dofs, first_rows, image_of):
    """(own slice, kept slice) per segment of the dofs and of the rows, and each segment's
    kept image index, the kept segment being its point image (``image_of(basis)``); None
    if a segment has none among the kept body's, two share one, or the sizes differ.
    ``kept``: a record with ``segments`` (weak references), ``first_dofs``, ``first_rows``."""
    index = {id(basis): k for k, ref in enumerate(kept.segments) if (basis := ref()) is not None}
    if len(index) != len(segments):
        return None
    columns, rows, found = [], [], []
    for k, basis in enumerate(segments):
        image = image_of(basis)
        j = index.get(id(image)) if image is not None else None
        if j is None or j in found:
            return None
        found.append(j)
        for own_first, kept_first, out in (
            (first_dofs, kept.first_dofs, columns),
            (first_rows, kept.first_rows, rows),
        ):
            own = slice(int(own_first[k]), int(own_first[k + 1]))
            other = slice(int(kept_first[j]), int(kept_first[j + 1]))
            if own.stop - own.start != other.stop - other.start:
                return None
            out.append((own, other))
    return columns, rows, found
