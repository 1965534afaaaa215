"""Bodies symmetric about the y axis: half of the regular rows integrated, the others mirrored.

The reflection M: (x, y) -> (-x, y) maps the outward normal to the outward normal and the
Kelvin kernels to themselves up to signs: T_ij(Mx, My, Mn) = s_i s_j T_ij(x, y, n) and
U_ij(Mx, My) = s_i s_j U_ij(x, y), s = (-1, 1). On a body whose every segment has a
mirror segment (traversed the other way: its functions in reverse order are the mirrored
ones), function b's mirror is function Q(b) and the collocation point of row i mirrors to
that of row Q(i), so the regular (non-singular) parts obey H[Q(i), Q(b)]_ij =
s_i s_j H[i, b]_ij, G alike. The assembly integrates one row of each mirrored pair and
fills the other; the rigid-body and singular terms come after, on the integrated rows only,
and the other rows are filled once more, whole (the kernels' symmetry holds for the singular
parts and the row sums too). The body is
symmetric to round-off (:data:`TOLERANCE`), so the filled rows agree with their own
integration to round-off, not bit for bit.

Which row of a pair is integrated is decided by x y (the larger), a rule that a point image
(:mod:`fretbem.bem.images`) keeps: the image body then integrates the image rows and takes
its blocks from the other body bit for bit.
"""

from __future__ import annotations

import sys
import weakref
from collections.abc import Sequence

import numpy as np

from fretbem.basis import Basis

from .mirror_split import Index

#: largest mismatch of a mirrored point, function value or Jacobian, relative to the body's
#: size (the reference pad is symmetric to 1.5e-14 of its height)
TOLERANCE = 1e-11


#: the outcome of each pair check of two discretised segments, per tolerance (and per
#: integration settings for the far rules'), by the segments' ids with weak references that
#: tell a live pair from a later one of the same ids: the adaptive levels keep every segment
#: but the contact face, so a level checks only the pairs its new face is in
_CHECKED: dict = {}

#: the checks kept at most (all are dropped past it: a few per segment pair)
CHECKED_MAX = 4096


def _known(a: Basis, b: Basis, key: tuple) -> bool | None:
    """The kept outcome of check ``key`` on the live pair (a, b), or None."""
    entry = _CHECKED.get((id(a), id(b), key))
    if entry is not None and entry[0]() is a and entry[1]() is b:
        return entry[2]
    return None


def _keep(a: Basis, b: Basis, key: tuple, outcome: bool) -> bool:
    """Keep (and return) the outcome of check ``key`` on the pair (a, b)."""
    if len(_CHECKED) >= CHECKED_MAX:
        _CHECKED.clear()
    _CHECKED[(id(a), id(b), key)] = (weakref.ref(a), weakref.ref(b), outcome)
    return outcome


def permutation(
    segments: Sequence[Basis],
    far_rules: Sequence[tuple] | None,
    points: np.ndarray,
    offsets,
    settings=None,
) -> np.ndarray | None:
    """Q, each function's (and collocation row's) mirror index, or None if the body is not
    symmetric about x = 0 to :data:`TOLERANCE` of its size.

    ``far_rules``: each segment's far rule (points, normals, J w, values per element and
    Gauss point, as :func:`fretbem.bem.assembly._segment_rules` keeps it): a mirror segment's,
    its elements and points in reverse order (the Gauss points are symmetric), are the
    segment's reflected, its values in reverse local order. None: not checked (a caller that
    checks the assembled matrices instead, :mod:`fretbem.bem.mirror_split`). ``settings``:
    the integration settings the far rules are of (each pair's far check is then kept).
    """
    scale = float(np.abs(points).max()) if points.size else 0.0
    if not scale > 0.0:
        return None
    tol = TOLERANCE * scale
    partner = []
    may = ("may", tol)
    for a in segments:
        found = []
        for j, b in enumerate(segments):
            mirrored = _known(a, b, may)
            if mirrored is None:
                mirrored = _keep(a, b, may, _may_mirror(a, b, tol))
            if mirrored:
                found.append(j)
        if len(found) != 1:
            return None
        partner.append(found[0])
    if any(partner[j] != k for k, j in enumerate(partner)):
        return None
    far = ("far", tol, settings)
    for k, j in enumerate(partner if far_rules is not None else ()):
        a, b = segments[k], segments[j]
        mirrored = None if settings is None else _known(a, b, far)
        if mirrored is None:
            mirrored = _mirrors(far_rules[k], far_rules[j], tol)
            if settings is not None:
                _keep(a, b, far, mirrored)
        if not mirrored:
            return None
    q = np.empty(int(offsets[-1]), dtype=np.intp)
    for k, j in enumerate(partner):
        count = segments[k].n_functions
        q[offsets[k] : offsets[k + 1]] = offsets[j] + count - 1 - np.arange(count)
    if np.abs(points[q] * [-1.0, 1.0] - points).max() > tol:
        return None
    return q


def _may_mirror(a: Basis, b: Basis, tol: float) -> bool:
    """Whether b can be a traversed backwards and reflected about x = 0: the same family and
    sizes, element e's local functions reversed are element E - 1 - e's (n - 1 - index),
    and its first geometry coefficient is b's last reflected (to ``tol``)."""
    if (
        type(a) is not type(b)
        or a.n_functions != b.n_functions
        or a.connectivity.shape != b.connectivity.shape
    ):
        return False
    (ax, ay), (bx, by) = a.geometry_coefficients[0], b.geometry_coefficients[-1]
    if abs(ax + bx) > tol or abs(ay - by) > tol:
        return False
    return bool(np.array_equal(b.connectivity[::-1, ::-1], a.n_functions - 1 - a.connectivity))


def _mirrors(a: tuple, b: tuple, tol: float) -> bool:
    """Whether far rule b, reversed, is far rule a reflected: points (to ``tol``), J w and
    the function values in reverse local order (to :data:`TOLERANCE`)."""
    (xa, _, wa, va), (xb, _, wb, vb) = a, b
    return bool(
        np.abs(xb[::-1, ::-1] * [-1.0, 1.0] - xa).max() <= tol
        and np.abs(wb[::-1, ::-1] - wa).max() <= TOLERANCE * np.abs(wa).max()
        and np.abs(vb[::-1, ::-1, ::-1] - va).max() <= TOLERANCE
    )


#: above this many filled rows :func:`fill` works in chunks of it by strided slices
FILL_CHUNK = 512
#: the module of the compiled assembly loops: once numba has loaded it, a fill is one
#: compiled pass (:func:`fretbem.bem.compiled_loops.fill_mirrored`)
_COMPILED = "fretbem.bem.compiled_loops"


def integrated_rows(q: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each row is integrated: one of each mirrored pair, the one with the larger
    x y (the smaller index on a tie), and every row that is its own mirror."""
    index = np.arange(len(q))
    xy = points[:, 0] * points[:, 1]
    other = xy[q]
    return (q == index) | (xy > other) | ((xy == other) & (index < q))


def fill(matrix: np.ndarray, q: np.ndarray, integrated: np.ndarray) -> None:
    """The rows not integrated, from their mirrors: M[Q(i), Q(b)]_ij = s_i s_j M[i, b]_ij."""
    Fill(q, integrated)(matrix)


class Fill:
    """:func:`fill` for one Q and one set of integrated rows, its indices (and for a small
    matrix its signs) worked out once for every matrix filled alike (an assembly fills H
    and G, twice)."""

    def __init__(self, q: np.ndarray, integrated: np.ndarray):
        missing = np.flatnonzero(~integrated)
        self.dofs = (2 * missing[:, None] + np.arange(2)).ravel()
        self.source = (2 * q[missing][:, None] + np.arange(2)).ravel()
        self.columns = (2 * q[:, None] + np.arange(2)).ravel()
        self.sign = np.tile([-1.0, 1.0], len(q))
        self.row_sign = self.sign[self.dofs]
        self._overlap = None

    def __call__(self, matrix: np.ndarray) -> None:
        if not self.dofs.size:
            return
        if (
            _COMPILED in sys.modules
            and matrix.flags.c_contiguous
            and matrix.dtype == np.float64
            and not self._reads_filled()
        ):
            # numba loaded (the compiled assembly loops): one pass, the same numbers
            sys.modules[_COMPILED].fill_mirrored(
                matrix, self.dofs, self.source, self.columns, self.sign
            )
            return
        if len(self.dofs) > FILL_CHUNK:
            _fill_by_slices(matrix, self.dofs, self.source, self.columns, self.sign)
            return
        # take along each axis (3x faster than fancy indexing twice); the sign product
        # s_i s_j is +-1, so one multiply gives the same numbers, signed zeros included
        block = matrix.take(self.source, axis=0).take(self.columns, axis=1)
        block *= np.multiply.outer(self.row_sign, self.sign)
        matrix[self.dofs] = block

    def _reads_filled(self) -> bool:
        """Whether a filled row is also a source row (never, for one of each mirrored pair
        integrated: then the rows may be filled in any order, in place)."""
        if self._overlap is None:
            self._overlap = bool(np.intersect1d(self.dofs, self.source).size)
        return self._overlap


def _fill_by_slices(matrix, dofs, source, columns, sign) -> None:
    """:func:`fill` of a large matrix, FILL_CHUNK rows at a time through reused buffers, the
    rows and columns gathered by strided slices (a mirror reverses whole segments:
    :class:`~fretbem.bem.mirror_split.Index`) where fancy indexing gathered every entry and
    held two copies of half the matrix; multiplying by s_j and then by s_i (each +-1) gives
    the numbers of one multiply by s_i s_j, signed zeros included."""
    width = matrix.shape[1]
    rows, block = np.empty((FILL_CHUNK, width)), np.empty((FILL_CHUNK, width))
    take_columns = Index(columns)
    for start in range(0, len(dofs), FILL_CHUNK):
        cut = slice(start, start + FILL_CHUNK)
        m = len(dofs[cut])
        Index(source[cut]).take(matrix, 0, rows[:m])
        take_columns.take(rows[:m], 1, block[:m])
        block[:m] *= sign
        block[:m] *= sign[dofs[cut], None]
        Index(dofs[cut]).put(matrix, block[:m], 0)
