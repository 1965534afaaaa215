"""The factorised collocation system of a BEM body and its condensed contact response.

H u = G t with the prescribed data moved right is factorised once per set of contact
segments; the loading-block displacement, the named load amplitudes and the contact
traction coefficients stay parameters, so every later solve is a triangular solve and
the contact response (:class:`~fretbem.body.ContactResponse`) is a few matrix products.
"""

from __future__ import annotations

import sys
import time
from typing import TYPE_CHECKING

import attrs
import numpy as np
import scipy.linalg as sla

from fretbem.body import BlockRotation, ContactResponse, RigidMotionError
from fretbem.numerics.blas import one_blas_thread
from fretbem.numerics.scatter import added_at

from . import image_factor, image_matrices, mirror, mirror_split
from .assembly import BLOCKS
from .layout import BLOCK, CONTACT, DISPLACEMENT, TRACTION, Layout

if TYPE_CHECKING:  # pragma: no cover
    from fretbem.body import Body


class BodySystem:
    """H u = G t with prescribed data moved right, factorised once.

    Unknowns z: u where traction is known (and on contact segments), t where displacement is
    known (and on the loading block). The loading-block displacement delta, the load
    amplitudes beta and the contact traction coefficients stay parameters:
    z = z0 + Z_delta delta + Z_beta beta + Z_contact t_contact.
    """

    def __init__(self, body: Body, contact_tags: tuple[str, ...]):
        self.body = body
        #: the system whose factors solved this one, this body being its point image
        #: (:mod:`fretbem.bem.image_factor`), or None
        self.image_of: BodySystem | None = None
        #: whether the contact rows of the contact columns are ``image_of``'s, by
        #: construction (its solution permuted, the contact dofs mapped in order:
        #: :func:`~fretbem.bem.image_factor.solve_permuted`)
        self.shares_contact_block = False
        self.contact_tags = tuple(contact_tags)
        layout = body.layout(contact_tags)
        g_free = g_free_segments(body, layout)
        source = body.permuted_source(g_free)
        start = time.perf_counter()
        self.kinds, self.known = layout.kinds.ravel(), layout.known.ravel()
        self.load_known = layout.loads.reshape(len(layout.loads), self.kinds.size)  # (k, 2N)
        solves_u = (self.kinds == TRACTION) | (self.kinds == CONTACT)
        self.solves_u = solves_u
        self.block_dofs = np.flatnonzero(self.kinds == BLOCK)
        self.contact_dofs = np.flatnonzero(self.kinds == CONTACT)
        contact = None  # the contact columns, where they are formed apart (a point image)
        with one_blas_thread():  # a busy machine made threaded BLAS 60x slower here
            response = None if source is None else _permuted_parameters(self, source)
            if response is not None:
                response, contact = response
            else:
                matrices = list(body.system_matrices(g_free))
                start = time.perf_counter()
                response = _solve_parameters(
                    self, matrices, self.kinds, self.known, self.load_known, solves_u,
                    self.block_dofs, self.contact_dofs,
                )  # fmt: skip
                del matrices  # the body releases its own copies once this system is cached
        if not np.all(np.isfinite(response)):
            raise RigidMotionError(
                f"body {body.name!r}: the collocation system is singular; check that the "
                "boundary conditions fix the rigid motions"
            )
        k = self.load_known.shape[0]
        self.base = response[:, 0]
        self.block_response = response[:, 1:3]
        self.load_response = response[:, response.shape[1] - k :]
        if contact is None:
            contact_columns = response[:, 3 : response.shape[1] - k]
            self._contact_response, self._contact_columns = contact_columns, None
        else:  # general columns only: the contact ones formed when first asked for
            self._contact_response, self._contact_columns = None, contact
        body.timings["factorisation"] = time.perf_counter() - start

    @property
    def contact_response(self) -> np.ndarray:
        """Z_contact (unknowns x contact dofs); for a point image served by its source's
        solution permuted, formed on first use (a run's contact response never asks)."""
        if self._contact_response is None:
            self._contact_response = self._contact_columns()
            self._contact_columns = None
        return self._contact_response

    def unknowns(self, delta, contact_tractions, loads=()) -> np.ndarray:
        """z = z0 + Z_delta delta + Z_contact t_contact + Z_beta beta."""
        beta = np.asarray(loads, float).reshape(-1)
        return (
            self.base
            + self.block_response @ np.asarray(delta, float)
            + self.contact_response @ np.asarray(contact_tractions, float)
            + self.load_response @ beta
        )

    def block_selector(self) -> np.ndarray:
        """(2, block dofs): the block's resultant force per unit of its traction unknowns."""
        weights = np.repeat(self.body.resultant_weights(self.block_segments()), 2)
        weights = weights[self.block_dofs]
        select = np.zeros((2, len(self.block_dofs)))
        select[self.block_dofs % 2, np.arange(len(self.block_dofs))] = weights
        return select

    def block_segments(self) -> list[int]:
        """The segments of the loading block's dofs."""
        functions = self.block_dofs // 2
        return np.unique(np.searchsorted(self.body.offsets, functions, side="right") - 1).tolist()

    def block_resultant(self, z: np.ndarray) -> np.ndarray:
        """Resultant force (2, ...) of the loading block's tractions in unknown vector(s) z."""
        return self.block_selector() @ z[self.block_dofs]

    def resultant_map(self) -> tuple[np.ndarray, np.ndarray]:
        """Block resultant force as r0 + K delta (with zero contact traction and loads)."""
        return self.block_resultant(self.base), self.block_resultant(self.block_response)

    def solution(self, delta, contact_tractions, loads=()) -> BodySolution:
        """Full displacement and traction coefficients for given block, contact and loads."""
        beta = np.asarray(loads, float).reshape(-1)
        delta = np.asarray(delta, float)
        z = self.unknowns(delta, contact_tractions, beta)
        known = self.known + beta @ self.load_known if beta.size else self.known
        u = np.where(self.solves_u, z, known)
        t = np.where(self.solves_u, known, z)
        u[self.block_dofs] = delta[self.block_dofs % 2]
        t[self.contact_dofs] = contact_tractions
        return BodySolution(self.body, u.reshape(-1, 2), t.reshape(-1, 2), delta)


def _permuted_parameters(owner: BodySystem, source) -> tuple | None:
    """(A^-1 [z0 rhs, block, load columns], A^-1 [contact columns] formed when called) of a
    body whose H and G are the kept
    body's permuted (``source``: :meth:`~fretbem.bem.body.BemBody.permuted_source`) and
    whose unknowns' kinds correspond, from that body's kept factors and solution, H and G
    never formed: only their columns on the known dofs are taken (the general parameter
    columns), the contact columns being the kept ones
    (:func:`~fretbem.bem.image_factor.solve_permuted`). The same numbers as solving with H
    and G permuted; None (then they are formed and solved as before) where the kept factors
    cannot serve so. 481 pairs: the specimen's system ~22 -> ~8 ms, and two 10 MB matrices
    fewer."""
    body = owner.body
    kept, columns, rows = source
    column_map = image_matrices.index_map(columns, len(owner.kinds))
    h, g = (_PermutedColumns(matrix, columns, rows) for matrix in (kept.h, kept.g))
    general = general_parameters(h, g, owner.kinds, owner.known, owner.load_known, owner.block_dofs)
    segments = body.segments
    first_dofs = 2 * body.offsets
    counts = np.bincount(body.collocation.segment, minlength=len(segments))
    first_rows = 2 * np.concatenate([[0], np.cumsum(counts)])
    shared = image_factor.solve_permuted(
        segments, first_dofs, first_rows, _image_of, general, owner.contact_dofs, column_map,
        solves_u=owner.solves_u, permuted_from=kept.h,
    )  # fmt: skip
    if shared is None:
        return None
    out, contact, owner.image_of = shared
    owner.shares_contact_block = True
    image_matrices.clear()  # served: the kept H and G are not needed any longer
    body.note_permuted()
    return out, contact


class _PermutedColumns:
    """A kept H or G seen as the permuted body's, for :func:`general_parameters`'s column
    takes ``matrix[:, dofs]`` (a boolean mask or indices) only: the same numbers as taken
    from the permuted matrix (:func:`~fretbem.bem.image_matrices.permuted_columns`)."""

    def __init__(self, matrix: np.ndarray, columns: list, rows: list):
        self.matrix, self.columns, self.rows = matrix, columns, rows

    def __getitem__(self, key) -> np.ndarray:
        rows, dofs = key
        if rows != slice(None):
            raise IndexError("only whole columns of a permuted matrix are taken")
        dofs = np.asarray(dofs)
        dofs = np.flatnonzero(dofs) if dofs.dtype == bool else dofs
        return image_matrices.permuted_columns(self.matrix, self.columns, self.rows, dofs)


def g_free_segments(body: Body, layout: Layout) -> tuple[int, ...]:
    """Segments whose G columns the system never reads: traction prescribed on both
    components, 0 and scaled by no load (G's columns meet only the known tractions there)."""
    free = (layout.kinds == TRACTION) & (layout.known == 0.0) & ~layout.loads.any(axis=0)
    return tuple(k for k in range(len(body.segments)) if free[body.function_slice(k)].all())


def _solve_parameters(
    owner, matrices, kinds, known, load_known, solves_u, block_dofs, contact_dofs
):
    """A^-1 [z0 rhs, block columns, contact columns, load columns], A the collocation matrix.

    ``matrices``: the list [H, G], emptied (and the body's own H and G released, for a
    system with contact faces, as :meth:`~fretbem.bem.body.BemBody.system` does once it is
    built) as soon as the halves of a large symmetric body are built: its LU and solves
    then run without H and G in memory.

    A body that is the point image of the body factorised just before, with corresponding
    boundary conditions, is solved with that one's factors (:mod:`fretbem.bem.image_factor`).
    A body symmetric about the y axis with symmetric conditions is solved as two half
    systems (:mod:`fretbem.bem.mirror_split`), built from H and G without A when it is too
    large to be kept for an image. Otherwise A and the parameters are built F-ordered
    (LAPACK's order) and factorised and solved in place, so at the peak H, G, the LU and the
    parameters are alive and nothing else dense. A is factorised with row pivoting, not as
    A^T (which moved the 961-pair unknowns by 1.4e-9: the condensed problem amplifies
    round-off). The LU is kept only for a point image (NaN if singular).
    """
    body = owner.body
    h, g = matrices
    split = _mirror_split(body, kinds)
    small = len(kinds) <= image_factor.KEEP_MAX_ROWS
    if split is not None and not small:
        halves = mirror_split.build(split, h, g, solves_u, contact_dofs)
        if halves is not None:
            image_factor.clear()
            general = general_parameters(h, g, kinds, known, load_known, block_dofs)
            del h, g
            matrices.clear()
            if owner.contact_tags:
                body.release_matrices()
            factor = mirror_split.SplitFactor(split, halves)
            del halves
            return _split_response(factor, general, contact_dofs)
    segments = body.segments
    first_dofs = 2 * body.offsets
    counts = np.bincount(body.collocation.segment, minlength=len(segments))
    first_rows = 2 * np.concatenate([[0], np.cumsum(counts)])
    # A is built only where it is solved or compared: not for H and G permuted from the body
    # factorised before (its point image: its factors serve when the kinds correspond), nor
    # for a body the halves solve unless a kept factorisation may serve it
    source = image_matrices.source_of(h)
    permuted_from = None if source is None else source.h
    general = None  # the parameter columns but the contact ones, where only they are formed
    if permuted_from is None and (
        split is None or image_factor.may_serve(segments, first_dofs, first_rows, _image_of)
    ):
        matrix, parameters = collocation_system(
            h, g, kinds, known, load_known, solves_u, block_dofs, contact_dofs
        )
    elif permuted_from is None:  # for the halves, which no kept factorisation may serve (no
        # A to compare): their contact right-hand sides are their own, and the contact
        # columns a point image may compare are formed only if it asks (481 pairs, 4 ms)
        matrix = parameters = None
        general = general_parameters(h, g, kinds, known, load_known, block_dofs)
    else:
        matrix = None
        parameters = collocation_parameters(
            h, g, kinds, known, load_known, block_dofs, contact_dofs
        )
    shared = None
    if parameters is not None:  # (without A or a permuted H, no kept factorisation serves)
        shared = image_factor.solve_as_image(
            segments, first_dofs, first_rows, _image_of, matrix, parameters,
            solves_u=solves_u, permuted_from=permuted_from,
        )  # fmt: skip
    if shared is not None:
        out, owner.image_of = shared
        if permuted_from is not None:  # served: the kept H and G are not needed any longer
            image_matrices.clear()
        return out
    halves = None if split is None else mirror_split.build(split, h, g, solves_u, contact_dofs)
    if halves is None and matrix is None:
        matrix = collocation_matrix(h, g, solves_u)
    if halves is None and parameters is None:
        parameters = collocation_parameters(
            h, g, kinds, known, load_known, block_dofs, contact_dofs
        )
    # kept for a point image: A (where it was built: a body the halves solve keeps none, and
    # only a body whose H and G are its own permuted takes its factors, 481 pairs 6 ms less)
    # and the parameters themselves where the halves solve (they leave both as they are),
    # copies where LAPACK overwrites them (481 pairs: two face-sized copies fewer, 19 MB)
    kept_matrix, kept_parameters = None, None
    if small:
        copy = halves is None
        kept_matrix = matrix.copy(order="F") if copy else matrix
        if parameters is None:
            kept_parameters = image_factor.LazyParameters(general, g, contact_dofs)
        else:
            kept_parameters = parameters.copy(order="F") if copy else parameters
    if halves is not None:
        del matrix
        factor = mirror_split.SplitFactor(split, halves)
        del halves
        if general is None:
            general = np.asfortranarray(
                np.delete(parameters, np.arange(3, 3 + len(contact_dofs)), axis=1)
            )
        out = _split_response(factor, general, contact_dofs)
        solve = None if factor.failed else factor.solve
    else:
        lu, piv, info = sla.lapack.dgetrf(matrix, overwrite_a=True)  # A = P L U
        del matrix
        if info != 0:
            image_factor.clear()
            return np.full(parameters.shape, np.nan)
        out, info = sla.lapack.dgetrs(lu, piv, parameters, overwrite_b=True)
        if info != 0:
            image_factor.clear()
            return np.full(parameters.shape, np.nan)
        solve = _LUSolve(lu, piv)
    if small and solve is not None:
        image_factor.keep(
            owner, segments, first_dofs, first_rows, kept_matrix, solve, kept_parameters, out,
            solves_u, h,
        )  # fmt: skip
    else:
        image_factor.clear()
    return out


class _LUSolve:
    """A^-1 b from A's LU factors (a kept factorisation's solve)."""

    def __init__(self, lu: np.ndarray, pivots: np.ndarray):
        self.lu, self.pivots = lu, pivots

    def __call__(self, rhs: np.ndarray) -> np.ndarray | None:
        out, info = sla.lapack.dgetrs(self.lu, self.pivots, rhs, overwrite_b=True)
        return None if info != 0 else out


def _mirror_split(body: Body, kinds: np.ndarray) -> mirror_split.MirrorSplit | None:
    """The body's mirror split (:mod:`fretbem.bem.mirror_split`) when its discretisation is
    symmetric about the y axis and so are its conditions (``kinds``), else None (and for a
    body of fewer than :data:`~fretbem.bem.mirror_split.MIN_ROWS` rows); the matrices are
    checked by the caller."""
    if len(kinds) < mirror_split.MIN_ROWS:
        return None
    if "mirror split" not in body._cache:
        colloc = body.collocation
        q = mirror.permutation(body.segments, None, colloc.points, body.offsets)
        body._cache["mirror split"] = (
            None
            if q is None
            else mirror_split.MirrorSplit.of(q, mirror.integrated_rows(q, colloc.points))
        )
    split = body._cache["mirror split"]
    return split if split is not None and split.symmetric_kinds(kinds) else None


def _split_response(factor, general, contact_dofs) -> np.ndarray:
    """[z0 rhs, block columns, contact columns, load columns] solved by the split factor
    (``general``: the other columns, z0 and block first), NaN if a half is singular."""
    size = general.shape[0]
    out = np.empty((size, general.shape[1] + len(contact_dofs)), order="F")
    solved = factor.solve(general)
    out[:, :3] = solved[:, :3]
    out[:, 3 + len(contact_dofs) :] = solved[:, 3:]
    if contact_dofs.size:
        factor.solve_contact(contact_dofs, out[:, 3 : 3 + len(contact_dofs)])
    if factor.failed:
        out[...] = np.nan
    return out


#: the segment a segment is the exact point image of (:func:`fretbem.bem.image_matrices.image_of`)
_image_of = image_matrices.image_of


def collocation_system(h, g, kinds, known, load_known, solves_u, block_dofs, contact_dofs):
    """The collocation matrix A (H with the columns of traction unknowns from -G) and the
    parameter columns [z0 rhs, block columns, contact columns, load columns], both F-ordered
    (benchmarks/dense_floor.py times their solve in other precisions)."""
    parameters = collocation_parameters(h, g, kinds, known, load_known, block_dofs, contact_dofs)
    return collocation_matrix(h, g, solves_u), parameters


def collocation_parameters(h, g, kinds, known, load_known, block_dofs, contact_dofs):
    """The parameter columns [z0 rhs, block columns, contact columns, load columns],
    F-ordered."""
    general = general_parameters(h, g, kinds, known, load_known, block_dofs)
    k = load_known.shape[0]
    parameters = np.empty((len(kinds), 3 + len(contact_dofs) + k), order="F")
    parameters[:, :3] = general[:, :3]
    contact = slice(3, 3 + len(contact_dofs))
    parameters[:, contact] = _taken(g, contact_dofs, axis=1)
    parameters[:, 3 + len(contact_dofs) :] = general[:, 3:]
    return parameters


def collocation_matrix(h, g, solves_u) -> np.ndarray:
    """The collocation matrix A, F-ordered: H with the columns of traction unknowns (not
    ``solves_u``) from -G."""
    matrix = _fortran_copy(h)
    solves_t = np.flatnonzero(~solves_u)
    matrix[:, solves_t] = -g[:, solves_t]
    return matrix


def general_parameters(h, g, kinds, known, load_known, block_dofs) -> np.ndarray:
    """The parameter columns other than the contact ones, F-ordered: [z0 rhs, block
    columns, load columns]."""
    fixed_u, fixed_t = kinds == DISPLACEMENT, kinds == TRACTION
    k = load_known.shape[0]
    out = np.empty((len(kinds), 3 + k), order="F")
    out[:, 0] = g[:, fixed_t] @ known[fixed_t] - h[:, fixed_u] @ known[fixed_u]
    for column in range(2):  # -h @ block columns: the block dofs of each direction summed
        dofs = block_dofs[block_dofs % 2 == column]
        out[:, 1 + column] = -h[:, dofs].sum(axis=1) if dofs.size else 0.0
    out[:, 3:] = g[:, fixed_t] @ load_known[:, fixed_t].T
    return out


def _fortran_copy(matrix: np.ndarray, tile: int = 512) -> np.ndarray:
    """``np.asfortranarray(matrix)`` for a C-ordered square matrix, copied tile by tile so
    that reads and writes stay in cache (7,838 rows: 0.17 s against 1.4 s)."""
    if matrix.flags.f_contiguous:
        return matrix.copy(order="F")
    out = np.empty(matrix.shape, order="F")
    transposed = out.T  # C-ordered view: out[i, j] is transposed[j, i]
    rows, cols = matrix.shape
    for i in range(0, rows, tile):
        for j in range(0, cols, tile):
            transposed[j : j + tile, i : i + tile] = matrix[i : i + tile, j : j + tile].T
    return out


def face_rows(body: Body, tag: str) -> tuple[np.ndarray, np.ndarray]:
    """Collocation rows and global function indices of the segments tagged ``tag`` (kept
    in the body's cache, read-only: the contact response asks for them four times)."""
    key = ("face rows", tag)
    if key not in body._cache:
        segments = sorted(body._indices(tag, "the contact pair"))
        rows = np.flatnonzero(np.isin(body.collocation.segment, segments))
        functions = np.concatenate(
            [np.arange(*body.function_slice(k).indices(body.n_functions)) for k in segments]
        )
        rows.flags.writeable = functions.flags.writeable = False
        body._cache[key] = rows, functions
    return body._cache[key]


def face_values_matrix(body: Body, tag: str) -> np.ndarray:
    """E of the contact face: coefficients to values at its collocation points (block diag).

    A segment whose assembly rules are kept (:data:`fretbem.bem.assembly.BLOCKS`) already
    holds its functions at its collocation points: E is built from those, the same numbers
    as :meth:`~fretbem.basis.Basis.collocation_matrix` evaluates again. Kept in the body's
    cache, read-only, for a face of at most :data:`FACE_VALUES_KEPT_MAX` functions (a point
    image's contact response compares it with its source's; a dense E of 3,841 nodes would
    hold 118 MB).
    """
    key = ("face values", tag)
    if key in body._cache:
        return body._cache[key]
    e_matrix = _face_values_matrix(body, tag)
    if len(e_matrix) <= FACE_VALUES_KEPT_MAX:
        e_matrix.flags.writeable = False
        body._cache[key] = e_matrix
    return e_matrix


#: the largest contact face (functions) whose E the body keeps (8 MB)
FACE_VALUES_KEPT_MAX = 1024


def _face_values_matrix(body: Body, tag: str) -> np.ndarray:
    segments = sorted(body._indices(tag, "the contact pair"))
    sizes = [body.segments[k].n_functions for k in segments]
    e_matrix = np.zeros((sum(sizes), sum(sizes)))
    colloc = body.collocation
    start = 0
    for k, n in zip(segments, sizes, strict=True):
        basis = body.segments[k]
        values = BLOCKS.collocation_values(basis, body.integration)
        if values is None or values.shape[0] != n:
            block = basis.collocation_matrix()
        else:
            elements = colloc.element[colloc.segment == k]
            block = added_at((n, n), (np.arange(n)[:, None], basis.connectivity[elements]), values)
        e_matrix[start : start + n, start : start + n] = block
        start += n
    return e_matrix


def contact_response(body: Body, tag: str) -> ContactResponse:
    """The face's displacement at its collocation points, affine in node tractions.

    Node traction values t become coefficients C t (C = E^-1); the system gives the
    face's displacement coefficients; E turns them back into node values. E is banded
    (a basis function spans a few collocation points), so both are banded operations on
    the face and block rows of the system's contact response only.
    """
    system = body.system((tag,))
    e_matrix = face_values_matrix(body, tag)
    band = _Band(e_matrix)
    n = band.size
    face_segments = sorted(body._indices(tag, "the contact pair"))
    face_weights = body.resultant_weights(face_segments)[face_rows(body, tag)[1]]
    image = _image_response(system, e_matrix, face_weights)

    def node_values(z: np.ndarray) -> np.ndarray:
        """Displacement values (n, 2, cols) at the face nodes from unknown columns z."""
        return band.left(z[system.contact_dofs].reshape(n, 2, z.shape[1]))

    if image is not None:  # the point image's maps: the same numbers (_image_response),
        # the same arrays, read-only (481 pairs: a 7.4 MB copy fewer)
        for shared in (image.traction_map, image.contact_force):
            shared.flags.writeable = False
        k = system.load_response.shape[1]
        return ContactResponse(
            base=node_values(system.base[:, None])[:, :, 0],
            traction_map=image.traction_map,
            block_map=np.zeros((n, 2, 2)),
            load_map=node_values(system.load_response),
            r_base=np.zeros(2),
            r_traction=np.zeros((2, 2 * n)),
            r_block=np.zeros((2, 2)),
            r_load=np.zeros((2, k)),
            contact_force=image.contact_force,
            has_block=False,
            rotation=None,
        )
    # Z (C x I2) on the face and block rows: solve E^T w = Z^T, Z^T with the node axis first;
    # built, solved and multiplied in place, so two face-sized arrays at most are alive
    rows = np.concatenate([system.contact_dofs, system.block_dofs])
    by_node = system.contact_response.T.reshape(n, 2, -1)  # [node a, component j, row]
    if n > ROW_SOLVE_MIN:  # node-major: E^-T along the first axis, row by row
        gathered = np.take(by_node, rows, axis=2).reshape(n, -1)  # [node a, (j, row)]
        transposed = band.solve_transposed_rows(gathered).reshape(n, 2, len(rows))
        by_row = transposed.transpose(2, 1, 0)
    else:
        transposed = np.empty((len(rows), 2, n))  # [row, j, node a]: E^T's right-hand sides
        for chunk in _chunks(len(rows)):
            transposed[chunk] = by_node[:, :, rows[chunk]].transpose(2, 1, 0)
        by_row = band.solve_transposed(transposed.reshape(-1, n).T).T.reshape(len(rows), 2, n)
    block_rows = by_row[2 * n :].transpose(0, 2, 1).reshape(-1, 2 * n).copy()  # [row, (b, j)]
    node_major = n > max(ROW_SOLVE_MIN, SPARSE_LEFT_MIN)  # [node a, j, row]; left by CSR
    if node_major and _COMPILED in sys.modules and transposed.flags.c_contiguous:
        traction_map = band.left_compiled(transposed)  # the same numbers, in one pass
        del by_row
    else:
        values = band.left(by_row[: 2 * n].reshape(n, 2, 2, n))  # [node b', j', j, node b]
        del by_row
        # the map goes into the right-hand sides' buffer (already in memory, as large)
        traction_map = transposed.reshape(-1)[: 4 * n * n].reshape(n, 2, 2 * n)
        traction_map.reshape(n, 2, n, 2)[...] = values.transpose(0, 1, 3, 2)
        del values
    del transposed
    weights = band.solve_transposed(face_weights[:, None].copy(order="F"))[:, 0]
    contact_force = np.zeros((2, 2 * n))
    contact_force[0, 0::2] = weights
    contact_force[1, 1::2] = weights
    k = system.load_response.shape[1]
    has_block = bool(system.block_dofs.size)
    if has_block:
        r_base, r_block, r_load = (
            system.block_resultant(z)
            for z in (system.base, system.block_response, system.load_response)
        )
        r_traction = system.block_selector() @ block_rows
    else:
        r_base, r_traction = np.zeros(2), np.zeros((2, 2 * n))
        r_block, r_load = np.zeros((2, 2)), np.zeros((2, k))
    rotation = None
    if has_block and not np.any(system.kinds == DISPLACEMENT):
        rotation = _block_rotation(body, tag, system, block_rows, band, face_segments)
    return ContactResponse(
        base=node_values(system.base[:, None])[:, :, 0],
        traction_map=traction_map,
        block_map=node_values(system.block_response) if has_block else np.zeros((n, 2, 2)),
        load_map=node_values(system.load_response),
        r_base=r_base,
        r_traction=r_traction,
        r_block=r_block,
        r_load=r_load.reshape(2, k),
        contact_force=contact_force,
        has_block=has_block,
        rotation=rotation,
    )


def _image_response(system: BodySystem, e_matrix, face_weights) -> ContactResponse | None:
    """The contact response of the body whose factors solved ``system`` (this body its point
    image, :mod:`fretbem.bem.image_factor`), when its traction map and contact force are
    this body's to the last bit and this body has no loading block; else None.

    Both are computed from the face's E, the face weights and the contact rows of the
    contact columns only, so they are equal when those three are, checked exactly (the
    contact rows only where they are not the source's by construction,
    :attr:`BodySystem.shares_contact_block`).
    """
    source = system.image_of
    if source is None or system.block_dofs.size or len(source.contact_tags) != 1:
        return None
    (tag,) = source.contact_tags
    response = source.body._cache.get(("response", tag))
    if response is None or len(source.contact_dofs) != len(system.contact_dofs):
        return None
    # equal by construction where the system took the source's solution permuted (its
    # contact dofs mapped to the source's in order): not compared again (481 pairs, 2.5 ms)
    if not system.shares_contact_block:
        own = _taken(system.contact_response, system.contact_dofs)
        other = _taken(source.contact_response, source.contact_dofs)
        if not np.array_equal(own, other):
            return None
    segments = sorted(source.body._indices(tag, "the contact pair"))
    weights = source.body.resultant_weights(segments)[face_rows(source.body, tag)[1]]
    if not np.array_equal(weights, face_weights):
        return None
    if not np.array_equal(face_values_matrix(source.body, tag), e_matrix):
        return None
    return response


def _taken(matrix: np.ndarray, index: np.ndarray, axis: int = 0) -> np.ndarray:
    """``matrix`` at ``index`` along ``axis`` (0 or 1), as a view when ``index`` runs
    consecutively (a contact face's dofs: no gathered copy of the face's block; the image
    check at 481 pairs 4.6 -> 1.5 ms)."""
    if index.size and index[-1] - index[0] == index.size - 1 and np.all(np.diff(index) == 1):
        span = slice(index[0], index[-1] + 1)
        return matrix[span] if axis == 0 else matrix[:, span]
    return matrix[index] if axis == 0 else matrix[:, index]


def _block_rotation(body, tag, system, block_rows, band, face_segments) -> BlockRotation:
    """The block's rotation for a body the block alone holds: a rotation theta of the block
    with no contact traction and no load turns the whole body rigidly (no traction
    anywhere), so its response is the rigid field, exactly; the block's moment is that of
    its traction unknowns, like its force."""
    colloc = body.collocation
    block_segments = body._indices(body.loading_block.tag, "the loading block")
    on_block = colloc.points[np.isin(colloc.segment, block_segments)]
    centre = on_block.mean(axis=0)
    # (N, 2), read on the block's dofs and the face only
    moments = body.moment_weights(centre, [*system.block_segments(), *face_segments])
    dofs = system.block_dofs
    selector = np.where(dofs % 2 == 0, -moments[dofs // 2, 1], moments[dofs // 2, 0])
    face_moments = band.solve_transposed(moments[face_rows(body, tag)[1]].copy(order="F"))
    contact_moment = np.column_stack([-face_moments[:, 1], face_moments[:, 0]]).ravel()
    face = colloc.points[face_rows(body, tag)[0]] - centre
    return BlockRotation(
        centre=centre,
        level=float(centre[1]),
        face_map=np.column_stack([-face[:, 1], face[:, 0]]),
        m_base=float(selector @ system.base[dofs]),
        m_traction=selector @ block_rows,
        m_block=selector @ system.block_response[dofs],
        m_rotation=0.0,
        m_load=selector @ system.load_response[dofs],
        r_rotation=np.zeros(2),
        contact_moment=contact_moment,
    )


#: the module whose import loads numba: once it is loaded, the banded solve along the node
#: axis runs compiled too (:meth:`_Band.solve_transposed_rows`)
_COMPILED = "fretbem.bem.compiled_loops"
#: face nodes above which ``_Band.left`` is one sparse product
SPARSE_LEFT_MIN = 200
#: face nodes above which the contact response solves E^T along the node axis of node-major
#: right-hand sides (:meth:`_Band.solve_transposed_rows`), not column by column with LAPACK
#: (whose elimination with L runs along rows of F-ordered columns): 481 pairs, 1,980
#: columns, the solve 12.6 -> 6.8 ms, the pad's response 24.1 -> 20.9 ms
#: (benchmarks/face_response.py; its traction map moves 5.5e-16 of its largest entry, the
#: reference cycle's unknowns 5e-12 of p_max, iterations equal); below, LAPACK's as before
ROW_SOLVE_MIN = 200


def _chunks(size: int, step: int = 512):
    """Slices of ``step`` covering range(size)."""
    return [slice(start, min(start + step, size)) for start in range(0, size, step)]


class _Band:
    """A banded square matrix E: products E @ x along the first axis and solves with E^T."""

    def __init__(self, matrix: np.ndarray):
        self.matrix = matrix
        self.size = len(matrix)
        rows, cols = np.nonzero(matrix)
        self.lower = int(max(np.max(rows - cols, initial=0), 0))
        self.upper = int(max(np.max(cols - rows, initial=0), 0))
        #: E[i, i + d] at index i for every diagonal d (0 where i + d is outside)
        self.diagonals = {}
        for d in range(-self.lower, self.upper + 1):
            diagonal = np.zeros(self.size)
            diagonal[max(-d, 0) : self.size - max(d, 0)] = np.diagonal(matrix, d)
            self.diagonals[d] = diagonal
        self._factor = None
        self._sparse = None

    def left(self, x: np.ndarray) -> np.ndarray:
        """E @ x along the first axis: for a face of more than :data:`SPARSE_LEFT_MIN` nodes as
        one sparse product, a single pass over x (7x faster at 481 pairs, and worth loading
        scipy.sparse, about 10 ms, which the run path does not otherwise); below, tile by tile,
        each tile of the product taking its few diagonals while it stays in cache, the terms
        of a row summed in diagonal order."""
        n = self.size
        shape, x = x.shape, x.reshape(n, -1)
        if n > SPARSE_LEFT_MIN:
            return (self._csr() @ x).reshape(shape)
        out = np.zeros(x.shape)
        for columns in _chunks(x.shape[1], 4096):
            tile = max(32, 2**15 // max(columns.stop - columns.start, 1))  # 256 kB and more
            for rows in _chunks(n, tile):
                for d in range(-self.lower, self.upper + 1):  # out[i] += E[i, i + d] x[i + d]
                    lo, hi = max(rows.start, -d), min(rows.stop, n - d)
                    if lo < hi:
                        out[lo:hi, columns] += (
                            self.diagonals[d][lo:hi, None] * x[lo + d : hi + d, columns]
                        )
        return out.reshape(shape)

    def _csr(self):
        """E as a scipy CSR array (built once: a contact response multiplies 5-7 times)."""
        if self._sparse is None:
            from scipy import sparse

            self._sparse = sparse.csr_array(self.matrix)
        return self._sparse

    def left_compiled(self, solved: np.ndarray) -> np.ndarray:
        """The traction map (n, 2, 2 n) from the solved node-major right-hand sides
        ``solved`` (n, 2, rows; C-ordered, the face's rows first): :meth:`left` of their
        face rows, transposed into the map's order, bit for bit, in one compiled pass
        (:func:`fretbem.bem.compiled_band.traction_map`; 481 pairs 11 -> 3.5-5 ms, and two
        face-sized arrays fewer)."""
        from . import compiled_band

        n = self.size
        csr = self._csr()
        out = np.empty((n, 2, n, 2))
        compiled_band.traction_map(csr.indptr, csr.indices, csr.data, solved, out)
        return out.reshape(n, 2, 2 * n)

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """E^-T rhs for rhs (n, cols), in place when rhs is F-ordered.

        ``scipy.linalg.solve_banded``'s own arithmetic (gbsv: gbtrf, then gbtrs on every
        column; gtsv for a tridiagonal E), with E^T factorised once for every solve and the
        columns taken in chunks that stay in cache (32 at 3,841 pairs: 1.41 -> 1.05 s for
        15,364 columns; all of a 61-pair face's ~300 in one call); each column's arithmetic
        is the same.
        """
        lower, upper = self.upper, self.lower  # bandwidths of E^T
        if lower == upper == 1 or self.size == 1 or rhs.ndim != 2 or not rhs.flags.f_contiguous:
            bands = self._transposed_bands()
            return sla.solve_banded(
                (lower, upper), bands, rhs, overwrite_b=True, check_finite=False
            )
        lu, pivots, _, _ = self._band_factor()
        # 32 columns or more, as many as fill 256 kB (a small face takes all in one call)
        width = max(32, 2**15 // self.size)
        for chunk in _chunks(rhs.shape[1], width):
            rhs[:, chunk], _ = sla.lapack.dgbtrs(lu, lower, upper, rhs[:, chunk], pivots)
        return rhs

    def solve_transposed_rows(self, rhs: np.ndarray) -> np.ndarray:
        """E^-T rhs in place for a C-ordered rhs (n, cols): LAPACK's band LU of E^T (the
        one :meth:`solve_transposed` uses) applied as gbtrs does, a row of rhs at a time,
        each step one vectorised update of the few rows the band reaches (the same
        operations per column in the same order, without fused multiply-adds); in a process
        that has loaded numba (the compiled assembly loops), the same operations in one
        compiled loop (:mod:`fretbem.bem.compiled_band`; 481 pairs 6.7 -> 1.7 ms)."""
        lu, pivots, lower, upper = self._band_factor()
        n = self.size
        if _COMPILED in sys.modules and rhs.flags.c_contiguous and rhs.dtype == np.float64:
            from . import compiled_band

            return compiled_band.solve_rows(lu, pivots, lower, upper, rhs)
        band = lower + upper  # U's superdiagonals (row ``band`` of ``lu`` is its diagonal)
        for j in range(n - 1):  # L: the row interchanges and the multipliers, in order
            p = pivots[j]
            if p != j:
                rhs[[j, p]] = rhs[[p, j]]
            reach = min(lower, n - 1 - j)
            if reach:
                rhs[j + 1 : j + 1 + reach] -= lu[band + 1 : band + 1 + reach, j, None] * rhs[j]
        for j in range(n - 1, -1, -1):  # U, from the last row up
            rhs[j] /= lu[band, j]
            first = max(0, j - band)
            if first < j:
                rhs[first:j] -= lu[band - (j - first) : band, j, None] * rhs[j]
        return rhs

    def _band_factor(self):
        """LAPACK's band LU of E^T (gbtrf, kept), its pivots and E^T's bandwidths."""
        lower, upper = self.upper, self.lower  # bandwidths of E^T
        if self._factor is None:
            factor = np.zeros((2 * lower + upper + 1, self.size), order="F")
            factor[lower:] = self._transposed_bands()
            lu, pivots, info = sla.lapack.dgbtrf(factor, lower, upper, overwrite_ab=True)
            if info != 0:
                raise np.linalg.LinAlgError("the face's collocation matrix E is singular")
            self._factor = lu, pivots
        return (*self._factor, lower, upper)

    def _transposed_bands(self) -> np.ndarray:
        """E^T in LAPACK's band storage (``solve_banded``'s ``ab``)."""
        lower, upper = self.upper, self.lower
        bands = np.zeros((lower + upper + 1, self.size))
        for d in range(-lower, upper + 1):  # E^T[i, i + d] = E[i + d, i] into row upper - d
            diagonal = np.diagonal(self.matrix, -d)
            if d >= 0:
                bands[upper - d, d:] = diagonal
            else:
                bands[upper - d, : self.size + d] = diagonal
        return bands


@attrs.frozen(eq=False)
class BodySolution:
    """Displacement and traction coefficients of a solved BEM body.

    Attributes
    ----------
    body : Body
    displacement_coefficients, traction_coefficients : ndarray, shape (N, 2)
    block_displacement : ndarray, shape (2,)
    """

    body: Body
    displacement_coefficients: np.ndarray
    traction_coefficients: np.ndarray
    block_displacement: np.ndarray

    def _field(self, coefficients, segment: int, params) -> np.ndarray:
        basis = self.body.segments[segment]
        return basis.evaluation_matrix(params) @ coefficients[self.body.function_slice(segment)]

    def displacement(self, segment: int, params) -> np.ndarray:
        """Displacement (m, 2) at curve parameters of one segment."""
        return self._field(self.displacement_coefficients, segment, params)

    def traction(self, segment: int, params) -> np.ndarray:
        """Traction (m, 2) at curve parameters of one segment."""
        return self._field(self.traction_coefficients, segment, params)

    def points(self, segment: int, params) -> np.ndarray:
        """Positions (m, 2) of the discretised geometry at curve parameters."""
        basis = self.body.segments[segment]
        return basis.geometry(*basis.to_local(params))[0]
