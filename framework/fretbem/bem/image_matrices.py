"""H and G of a body that is the exact point image of the body assembled just before.

A body whose every segment is the exact point image of a segment of the last body assembled
(:mod:`fretbem.bem.images`: the same family, parameterisation and functions, the geometry
negated bit for bit; told by :func:`image_of`), with the same Kelvin kernel and integration
settings, has that body's H and G with their rows and columns permuted segment by segment:
the kernels are even in the offset and the normal together, so each regular, near and
singular integral is the other body's to the last bit, and the collocation points and
functions map one to one within a segment. Only the rigid-body terms on the diagonal would
come out at round-off of the other body's if integrated again (row sums taken in the body's
own segment order). The reference scene's pad and specimen, two similar cylinders, are such
images: the specimen's H and G are the pad's permuted, not assembled and compared
(:mod:`fretbem.bem.image_factor` then needs no block check either, :func:`source_of`).
Where the kept factorisation serves its system, they are not even formed: only their
columns on its known dofs are taken (:func:`permutation`, :func:`permuted_columns`).
Every other body (another material, shape, mesh, settings) is assembled as before.
"""

from __future__ import annotations

import weakref

import attrs
import numpy as np

from . import images
from .assembly import BLOCKS
from .image_factor import segment_map

#: the largest body (rows of H) whose H and G are kept for its point image: the size the
#: kept factorisation allows (:data:`fretbem.bem.image_factor.KEEP_MAX_ROWS`), 64 MB at most
KEEP_MAX_ROWS = 2048


def image_of(basis):
    """The segment ``basis`` is the exact point image of: kept by the block store, or (a body
    too large to keep its blocks) the one it was discretised from
    (:func:`fretbem.bem.images.source`); None if neither."""
    image = BLOCKS.image(basis)
    return image if image is not None else images.source(basis)


@attrs.frozen(eq=False)
class KeptMatrices:
    """The last body's H and G (its own arrays, never written after the assembly), its
    segments (weak), their first dofs and first rows, the kernel's (shear modulus,
    effective nu), the integration settings (``compiled`` left out: both loops integrate
    alike to round-off) and the segments whose G columns may be 0 (``g_free``)."""

    segments: tuple
    first_dofs: np.ndarray
    first_rows: np.ndarray
    kernel: tuple
    settings: object
    g_free: frozenset
    h: np.ndarray
    g: np.ndarray


_KEPT: list[KeptMatrices | None] = [None]
#: each derived H (by id, with a weak reference that tells it from a later array of the same
#: id): the kept matrices it was permuted from
_DERIVED: dict = {}


def clear() -> None:
    """Forget the kept matrices and what was derived from them."""
    _KEPT[0] = None
    _DERIVED.clear()


def keep(segments, first_dofs, first_rows, kernel, settings, g_free, h, g) -> None:
    """Keep a body's H and G (not copied) for its point image, if it is small enough; else
    forget the last ones. They are kept until the next body is assembled, or until a system
    built from H and G permuted from them is solved with their body's factors
    (:func:`fretbem.bem.system._solve_parameters`)."""
    clear()
    if len(h) > KEEP_MAX_ROWS:
        return
    _KEPT[0] = KeptMatrices(
        tuple(weakref.ref(basis) for basis in segments),
        first_dofs,
        first_rows,
        kernel,
        _settings_key(settings),
        frozenset(g_free),
        h,
        g,
    )


def permutation(segments, first_dofs, first_rows, kernel, settings, g_free):
    """(kept matrices, column map, row map) when a body of these segments has the kept
    body's H and G permuted (:func:`derived`'s conditions), without forming them; else None.
    The maps are (own slice, kept slice) pairs, consecutive ones merged."""
    kept = _KEPT[0]
    if kept is None or kept.kernel != kernel or kept.settings != _settings_key(settings):
        return None
    mapped = segment_map(kept, segments, first_dofs, first_rows, image_of)
    if mapped is None:
        return None
    columns, rows, images_of = mapped
    if any(j in kept.g_free and k not in g_free for k, j in enumerate(images_of)):
        return None
    return kept, _runs(columns), _runs(rows)


def derived(segments, first_dofs, first_rows, kernel, settings, g_free):
    """(H, G) permuted from the kept body's when every segment is the exact point image of
    one of its segments (:func:`image_of`, one to one, as many dofs and rows) and the kernel
    and settings are equal, and the kept G holds every column the caller reads (none of
    its ``g_free`` segments is the image of a segment outside ``g_free``); else None."""
    found = permutation(segments, first_dofs, first_rows, kernel, settings, g_free)
    if found is None:
        return None
    kept, columns, rows = found
    h, g = np.empty(kept.h.shape), np.empty(kept.g.shape)
    for out, source in ((h, kept.h), (g, kept.g)):  # block by block, by slices
        for own_rows, kept_rows in rows:
            for own, other in columns:
                out[own_rows, own] = source[kept_rows, other]
    for array in (h, g):
        _DERIVED[id(array)] = (weakref.ref(array), kept)
    return h, g


def permuted_columns(matrix: np.ndarray, columns: list, rows: list, dofs: np.ndarray):
    """``derived``'s permuted ``matrix`` (the kept H or G) at columns ``dofs`` only (every
    row), the same numbers: its columns taken, then its rows permuted."""
    column_map = index_map(columns, matrix.shape[1])
    taken = matrix[:, column_map[dofs]]
    out = np.empty_like(taken)  # in the layout numpy's column take gives (its products' sums)
    for own, other in rows:
        out[own] = taken[other]
    return out


def index_map(pairs: list, size: int) -> np.ndarray:
    """The kept index of each own index, from (own slice, kept slice) pairs."""
    out = np.empty(size, dtype=np.intp)
    for own, other in pairs:
        out[own] = np.arange(other.start, other.stop)
    return out


def source_of(h: np.ndarray) -> KeptMatrices | None:
    """The kept matrices ``h`` was permuted from (:func:`derived`), or None."""
    entry = _DERIVED.get(id(h))
    return entry[1] if entry is not None and entry[0]() is h else None


def _runs(pairs: list) -> list:
    """(own slice, kept slice) pairs with consecutive ones merged where both continue each
    other (a cyclic shift of the segments is two runs): fewer, longer copies."""
    out = [pairs[0]]
    for own, other in pairs[1:]:
        last_own, last_other = out[-1]
        if own.start == last_own.stop and other.start == last_other.stop:
            out[-1] = (slice(last_own.start, own.stop), slice(last_other.start, other.stop))
        else:
            out.append((own, other))
    return out


def _settings_key(settings):
    """The settings as they decide the numbers: which loops integrate them is left out."""
    return attrs.evolve(settings, compiled=None)
