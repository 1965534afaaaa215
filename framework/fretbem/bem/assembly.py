"""The collocation assembly of :class:`fretbem.bem.integration.Assembler`, on either loops.

The pair loops (classify, integrate far and mid pairs, scatter) come from
:mod:`fretbem.bem.compiled_loops` (numba) or :mod:`fretbem.bem.numpy_loops`;
both give H and G equal to
the round-1 assembler to round-off (tests/framework/test_assembly_compiled.py). The
plugin's basis is evaluated in as few calls as possible: one per segment for the far and
mid rules, the distance samples, the collocation points and every singular rule; one more
for the near pairs' graded rules. Nothing of size (2N)^2 is allocated besides H and G.
"""

from __future__ import annotations

import collections
import weakref

import numpy as np

from fretbem.numerics.graded import graded_rule
from fretbem.numerics.quadrature import QuadratureRule

from . import images, mirror

#: closest-point start samples per element; every other one is a distance sample of the
#: classification (np.linspace(-1, 1, 9), exactly: the spacings are powers of two)
START = np.linspace(-1.0, 1.0, 17)
SAMPLES = START[::2]


def _singular_rules(center: np.ndarray, settings) -> list[dict]:
    """Both sides of elements split at local ``center``: Gauss and log rules (Assembler)."""
    gauss = QuadratureRule.gauss_legendre(settings.singular_points)
    u_gauss, w_gauss = 0.5 * (gauss.points + 1.0), 0.5 * gauss.weights  # on [0, 1]
    log_rule = QuadratureRule.gauss_log(settings.log_points)
    sides = []
    for side in (-1.0, 1.0):
        length = np.where(side < 0, center + 1.0, 1.0 - center)  # local units
        live = length > 1e-12
        safe = np.where(live, length, 1.0)
        t = safe[:, None] * u_gauss
        sides.append(
            {
                "t": t,
                "safe": safe,
                "local": np.where(live[:, None], center[:, None] + side * t, 0.0),
                "log_local": np.where(
                    live[:, None], center[:, None] + side * safe[:, None] * log_rule.points, 0.0
                ),
                "weights": safe[:, None] * w_gauss * live[:, None],
                "log_weights": safe[:, None] * log_rule.weights * live[:, None],
            }
        )
    return sides


def _closest(basis, elements, sources, start_points, start_tangents, iterations: int = 3):
    """Closest local coordinate and distance, as the numpy path's ``_closest_local``.

    The start is the nearest of 17 samples; an end sample that the first Gauss-Newton step
    pushes outward is kept by the clip at every iteration, so it is final without
    evaluating the basis again (the usual case: a neighbour element's shared end).
    """
    dist = np.linalg.norm(start_points[elements] - sources[:, None], axis=-1)
    index = np.argmin(dist, axis=1)
    eta = START[index]
    x = start_points[elements, index]
    tangent = start_tangents[elements, index]
    step = np.sum((x - sources) * tangent, axis=-1) / np.sum(tangent**2, axis=-1)
    settled = ((index == 0) & (step >= 0.0)) | ((index == START.size - 1) & (step <= 0.0))
    distance = np.linalg.norm(x - sources, axis=-1)
    todo = np.flatnonzero(~settled)
    if todo.size:
        e, src, eta_t = elements[todo], sources[todo], eta[todo]
        for _ in range(iterations):
            xt, tt, *_ = basis.geometry(e, eta_t)
            st = np.sum((xt - src) * tt, axis=-1) / np.sum(tt**2, axis=-1)
            eta_t = np.clip(eta_t - st, -1.0, 1.0)
        xt, *_ = basis.geometry(e, eta_t)
        eta[todo] = eta_t
        distance[todo] = np.linalg.norm(xt - src, axis=-1)
    return eta, distance


def _contiguous(*arrays):
    return tuple(np.ascontiguousarray(a) for a in arrays)


#: bodies up to this many functions keep their blocks for reuse (the adaptive mode stops at 241
#: pairs, 319 functions in the reference scene; H and G of 400 functions
#: are 10 MB; a large body is assembled once, so a copy would only raise its peak memory)
REUSE_MAX_FUNCTIONS = 400


#: bodies whose segments keep their blocks (the adaptive mode assembles two per level)
RECENT_BODIES = 4

#: bodies up to this many functions (above :data:`REUSE_MAX_FUNCTIONS`) lend their rules to
#: the next body assembled only, then forget them (the reference specimen, the pad's point
#: image, tells itself one by them at 481 pairs, 559 functions). They keep no blocks: the
#: only body that took them, the point image, now takes the whole H and G permuted
#: (:mod:`fretbem.bem.image_matrices`) or never forms them, so their copies (20 MB, 5 ms of
#: the 481-pair cycle, 18 ms on a loaded machine) were never read
LEND_MAX_FUNCTIONS = 600


class BlockStore:
    """The regular part (far, mid and near pairs) of H and G per pair of discretised segments,
    and each segment's fixed rules.

    The block of the rows collocated on segment r against the functions of segment k depends
    only on those two discretisations, the kernel, the rules and the loops; the rigid-body
    and singular terms come after it. A body re-meshed on one segment (the adaptive mode's
    levels) keeps the other segments' Basis objects, so their blocks are taken from here
    instead of being integrated again. Keys are weak: a block goes with its segments. Only
    the segments of the last :data:`RECENT_BODIES` bodies assembled keep theirs: a segment
    that every level shares stays, each level's re-meshed face goes (its Basis may live on
    in the boundary's own cache of discretisations, its blocks do not).

    A segment that is the exact point image of a kept one (:mod:`fretbem.bem.images`: the
    specimen of two similar cylinders against the pad) takes that one's blocks and its rules
    reflected: the same numbers its own integration gives, bit for bit.
    """

    def __init__(self) -> None:
        self._blocks: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._rules: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._recent: collections.deque = collections.deque(maxlen=RECENT_BODIES)
        self._lent: tuple | None = None  # the last body's segments, if it only lends them
        #: each segment's (own, image's) signature, and the kept segments by signature
        self._signatures: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._by_signature: weakref.WeakValueDictionary = weakref.WeakValueDictionary()

    def assembled(self, segments, lent: bool = False) -> None:
        """Record a body's segments; forget what no recent body uses. A body ``lent`` keeps
        its rules and blocks for the next body assembled only."""
        if self._lent is not None and self._lent in self._recent:
            self._recent.remove(self._lent)
        entry = tuple(weakref.ref(b) for b in segments)
        self._recent.append(entry)
        self._lent = entry if lent else None
        live = {id(b) for body in self._recent for r in body if (b := r()) is not None}
        for store in (self._blocks, self._rules):
            for basis in [b for b in store.keys() if id(b) not in live]:
                del store[basis]
        for by_rows in self._blocks.values():
            for basis in [b for b in by_rows.keys() if id(b) not in live]:
                del by_rows[basis]

    def get(self, columns, rows, key):
        """The (H, G) block of ``rows``' points against ``columns``' functions (or of their
        point images' points and functions: the same numbers), or None."""
        block = self._blocks.get(columns, {}).get(rows, {}).get(key)
        if block is not None:
            return block
        columns, rows = self.image(columns), self.image(rows)
        if columns is None or rows is None:
            return None
        return self._blocks.get(columns, {}).get(rows, {}).get(key)

    def _signature(self, basis) -> tuple[bytes, bytes] | None:
        if basis not in self._signatures:
            # a segment discretised as a kept one's point image has that one's digests
            # swapped (its fields the same, its geometry the negated one's, zeros +0)
            source = images.source(basis)
            known = self._signatures.get(source) if source is not None else None
            self._signatures[basis] = (
                images.signatures(basis) if known is None else (known[1], known[0])
            )
        return self._signatures[basis]

    def image(self, basis):
        """The kept segment (its rules kept) that is ``basis``'s exact point image, or None."""
        source = images.source(basis)  # discretised as that one's image: no digest needed
        if source is not None and source in self._rules:
            return source
        signature = self._signature(basis)
        if signature is None:
            return None
        found = self._by_signature.get(signature[1])
        return found if found is not None and found in self._rules else None

    def put(self, columns, rows, key, h_block, g_block) -> None:
        """Keep a block (copies)."""
        by_rows = self._blocks.setdefault(columns, weakref.WeakKeyDictionary())
        by_rows.setdefault(rows, {})[key] = (h_block.copy(), g_block.copy())

    def rules(self, basis, settings) -> dict | None:
        """The fixed rules of one segment (:func:`_segment_rules`; a kept point image's
        reflected, then kept for it), or None."""
        rules = self._rules.get(basis, {}).get(settings)
        if rules is None and (image := self.image(basis)) is not None:
            kept = self._rules[image].get(settings)
            if kept is not None:
                rules = images.reflected_rules(kept)
                self.keep_rules(basis, settings, rules)
        return rules

    def collocation_values(self, basis, settings) -> np.ndarray | None:
        """The segment's local functions at its own collocation points, (points, n_local),
        as its rules hold them (the rows of its E matrix), or None if not kept."""
        rules = self.rules(basis, settings)
        return None if rules is None else rules["values"]

    def keep_rules(self, basis, settings, rules: dict) -> None:
        """Keep a segment's rules (read-only from here on)."""
        self._rules.setdefault(basis, {})[settings] = rules
        signature = self._signature(basis)
        if signature is not None:
            self._by_signature[signature[0]] = basis

    def clear(self) -> None:
        """Forget every block and rule (tests, benchmarks)."""
        self._blocks = weakref.WeakKeyDictionary()
        self._rules = weakref.WeakKeyDictionary()
        self._recent.clear()
        self._lent = None
        self._by_signature = weakref.WeakValueDictionary()


#: the process's store of regular blocks (see :class:`BlockStore`)
BLOCKS = BlockStore()


def _segment_rules(basis, settings, element, local, parameter) -> dict:
    """Every fixed rule of one segment, from one basis evaluation.

    The far and mid rules and the distance samples of every element, the basis at the
    segment's own collocation points (``element``, ``local``, ``parameter``) and both sides
    of the singular rules of those points: all depend on the segment and the rules only.
    """
    far_rule = QuadratureRule.gauss_legendre(settings.far_points)
    mid_rule = QuadratureRule.gauss_legendre(settings.mid_points)
    per_element = np.concatenate([far_rule.points, mid_rule.points, START])
    cut = np.cumsum([0, far_rule.points.size, mid_rule.points.size, START.size])
    n_el = basis.n_elements
    # singular pairs depend only on parameters: the element(s) holding each point
    lo, hi = basis.element_bounds.T
    sr, se = np.nonzero((parameter[:, None] >= lo - 1e-12) & (parameter[:, None] <= hi + 1e-12))
    lo_s, hi_s = basis.element_bounds[se].T
    center = np.clip(2.0 * (parameter[sr] - lo_s) / (hi_s - lo_s) - 1.0, -1, 1)
    sides = _singular_rules(center, settings)
    singular_local = np.concatenate(
        [center[:, None]] + [np.concatenate([d["local"], d["log_local"]], 1) for d in sides],
        axis=1,
    )
    m = basis.map(
        np.concatenate([np.repeat(np.arange(n_el), per_element.size), element]),
        np.concatenate([np.tile(per_element, n_el), local]),
    )
    a0 = n_el * per_element.size
    a1 = a0 + element.size

    def per_el(array, part):
        return array[:a0].reshape(n_el, per_element.size, *array.shape[1:])[
            :, cut[part] : cut[part + 1]
        ]

    far = _contiguous(
        per_el(m.points, 0),
        per_el(m.normals, 0),
        per_el(m.jacobians, 0) * far_rule.weights,
        per_el(m.values, 0),
    )
    mid = _contiguous(
        per_el(m.points, 1),
        per_el(m.normals, 1),
        per_el(m.jacobians, 1) * mid_rule.weights,
        per_el(m.values, 1),
    )
    samples = np.ascontiguousarray(per_el(m.points, 2)[:, ::2])
    centres = 0.5 * (samples.max(axis=1) + samples.min(axis=1))
    return {
        "far": far,
        "mid": mid,
        "samples": samples,
        "length": mid[2].sum(axis=1),
        "centres": centres,
        "radii": np.linalg.norm(samples - centres[:, None], axis=-1).max(axis=1),
        "start_points": per_el(m.points, 2),
        "start_tangents": per_el(m.tangents, 2),
        "values": m.values[a0:a1],
        "singular_rows": sr,
        "singular_elements": se,
        "singular_sides": SingularRules(basis, se, singular_local, sides, settings),
    }


class SingularRules:
    """Both sides' rules of a segment's singular pairs (its collocation points on their own
    elements), the basis evaluated on first use and only at the pairs asked for: a mirrored
    body integrates the singular terms of half its rows (481 pairs: 27,000 of the rules'
    46,000 basis evaluations were singular points, half never used). Every evaluation is
    pointwise, so the numbers are those of one evaluation of every pair. A point image's
    are its source's with the points and normals negated (:meth:`reflected`)."""

    def __init__(self, basis, elements, local, sides, settings, source=None):
        self._basis = None if basis is None else weakref.ref(basis)  # rules are kept per basis
        self.elements, self.local, self.sides, self.settings = elements, local, sides, settings
        self._source = source
        self._every = None

    def reflected(self) -> SingularRules:
        """The rules of this segment's point image."""
        return SingularRules(None, self.elements, self.local, self.sides, self.settings, self)

    def arrays(self, on: np.ndarray | None = None) -> tuple:
        """The arguments of ``integrate_singular`` (:func:`_singular_sides`) for the pairs
        ``on`` (a mask over them; None: every pair, kept)."""
        if on is None and self._every is not None:
            return self._every
        if self._source is not None:
            out = tuple(
                images._negated(a) if i in images.NEGATED["singular_sides"] else a
                for i, a in enumerate(self._source.arrays(on))
            )
        else:
            pairs = slice(None) if on is None else on
            elements, local = self.elements[pairs], self.local[pairs]
            q_sing = local.shape[1]
            m = self._basis().map(np.repeat(elements, q_sing), local.ravel())
            data = {
                name: getattr(m, name).reshape(len(elements), q_sing, *getattr(m, name).shape[1:])
                for name in ("points", "normals", "jacobians", "values")
            }
            sides = [{key: value[pairs] for key, value in side.items()} for side in self.sides]
            out = _singular_sides(data, sides, self.settings)
        if on is None:
            self._every = out
        return out


def _singular_sides(data: dict, sides: list[dict], settings) -> tuple:
    """The arguments of ``integrate_singular`` for both sides of the split elements at once
    (side -1's pairs, then side +1's): points, normals, J w and values of the Gauss rule,
    the values at the source, t, the side lengths, J w and values of the log rule."""
    q_gauss, q_log = settings.singular_points, settings.log_points
    at_source = data["values"][:, 0]
    parts = []
    start = 1
    for side in sides:
        gauss = slice(start, start + q_gauss)
        log = slice(start + q_gauss, start + q_gauss + q_log)
        start += q_gauss + q_log
        parts.append(
            (data["points"][:, gauss], data["normals"][:, gauss],
             data["jacobians"][:, gauss] * side["weights"], data["values"][:, gauss],
             at_source, side["t"], side["safe"], data["jacobians"][:, log] * side["log_weights"],
             data["values"][:, log])
        )  # fmt: skip
    return _contiguous(*(np.concatenate(pair) for pair in zip(*parts, strict=True)))


#: each segment's singular elements and rule sides on the rows a mirrored body integrates,
#: per settings and row pattern (weak keys: the adaptive levels keep every segment but the
#: contact face, and integrate the same rows of each)
_SINGULAR_ON: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _integrated_singular(basis, settings, on: np.ndarray, elements, singular) -> tuple:
    """``elements[on]`` and every singular side array at the pairs of both sides on ``on``
    (the segment's singular rows a mirrored body integrates), kept per segment."""
    kept = _SINGULAR_ON.setdefault(basis, {})
    key = (settings, on.tobytes())
    if key not in kept:
        kept[key] = (elements[on], singular.arrays(on))
    return kept[key]


def _rows_outside(starts: np.ndarray, segments) -> np.ndarray:
    """The collocation rows of no segment in ``segments`` (rows in segment order, segment r's
    from ``starts[r]`` to ``starts[r + 1]``): ``np.isin`` on the rows' segments without its
    sort (60 us a call, six calls per body)."""
    keep = np.ones(int(starts[-1]), bool)
    for r in segments:
        keep[starts[r] : starts[r + 1]] = False
    return np.flatnonzero(keep)


def _row_sums(h: np.ndarray, n: int, chunk: int = 64) -> np.ndarray:
    """``h.reshape(-1, 2, n, 2).sum(axis=2)`` (h: rows of the 2n columns), bit for bit, at a
    third of its time.

    numpy sums that strided axis in order, column pair after column pair; here each chunk of
    rows is laid out with the column pairs outermost and summed in the same order over
    contiguous rows (a chunk at a time, so no copy of H is ever whole).
    """
    out = np.empty((len(h), 2))
    for start in range(0, len(h), chunk):
        block = h[start : start + chunk].reshape(-1, n, 2)
        out[start : start + chunk] = np.ascontiguousarray(block.transpose(1, 0, 2)).sum(axis=0)
    return out.reshape(-1, 2, 2)


def _rigid_row_sums(loops, h: np.ndarray, n: int, integrated: np.ndarray | None) -> np.ndarray:
    """(n, 2, 2) row sums of H over each function's rows, for the rows ``integrated`` (every
    row if None; the others 0): :func:`_row_sums`' numbers, computed in place by the compiled
    loops where they are used (481 pairs: 4 ms -> 0.5 ms, the gathered half of H and its
    transposed chunks never made)."""
    on = np.arange(n) if integrated is None else np.flatnonzero(integrated)
    compiled = getattr(loops, "row_sums", None)
    if compiled is not None and h.flags.c_contiguous and h.dtype == np.float64:
        out = np.zeros((n, 2, 2))
        compiled(h, on.astype(np.intp), n, out)
        return out
    if integrated is None:
        return _row_sums(h, n)
    out = np.zeros((n, 2, 2))
    out[on] = _row_sums(h[(2 * on[:, None] + np.arange(2)).ravel()], n)
    return out


def _near(loops, basis, rules, points, pr, pe, cols, s, kernel, h, g, with_g) -> None:
    """Near pairs (row ``pr[p]``, element ``pe[p]``) on rules graded toward each row's
    closest point of its element, into H and G (G only ``with_g``)."""
    center_near, distance = _closest(
        basis, pe, points[pr], rules["start_points"], rules["start_tangents"]
    )
    local, weights = graded_rule(
        center_near, 2.0 * distance / rules["length"][pe], s.graded_points, s.graded_ratio
    )
    near_map = basis.map(np.repeat(pe, local.shape[1]), local.ravel())
    shape = local.shape
    loops.integrate_pairs(
        pr, points, near_map.points.reshape(*shape, 2), near_map.normals.reshape(*shape, 2),
        near_map.jacobians.reshape(shape) * weights, near_map.values.reshape(*shape, -1),
        cols[pe], *kernel, h, g, *(() if with_g else (False,)),
    )  # fmt: skip


def assemble(
    assembler, shear_modulus: float, nu: float, loops, g_free: frozenset = frozenset()
) -> tuple[np.ndarray, np.ndarray]:
    """Dense H and G of ``assembler`` (an :class:`~fretbem.bem.integration.Assembler`).

    ``loops`` is :mod:`fretbem.bem.compiled_loops` or :mod:`fretbem.bem.numpy_loops`. A body
    of at most :data:`REUSE_MAX_FUNCTIONS` takes the rules and regular blocks of segments
    it shares with bodies assembled before (:data:`BLOCKS`) and keeps its own (one of at
    most :data:`LEND_MAX_FUNCTIONS` alike, keeping its rules only, for the next body). The numpy
    loops leave G's columns of the segments numbered in ``g_free`` at 0 (a solve that
    never reads them: traction-free segments); H is the same either way.
    """
    n, s, colloc = assembler.n, assembler.settings, assembler.colloc
    h, g = np.zeros((2 * n, 2 * n)), np.zeros((2 * n, 2 * n))
    segments = assembler.segments
    reuse = n <= LEND_MAX_FUNCTIONS
    keeps_blocks = n <= REUSE_MAX_FUNCTIONS
    skips_g = getattr(loops, "SKIPS_G", False)
    starts = np.searchsorted(colloc.segment, np.arange(len(segments) + 1))  # rows in order
    with_g = [not (skips_g and k in g_free) for k in range(len(segments))]
    all_rules = []
    for k, basis in enumerate(segments):
        rules = BLOCKS.rules(basis, s) if reuse else None
        if rules is None:
            rows = slice(starts[k], starts[k + 1])
            rules = _segment_rules(
                basis, s, colloc.element[rows], colloc.local[rows], colloc.parameter[rows]
            )
            if reuse:
                BLOCKS.keep_rules(basis, s, rules)
        all_rules.append(rules)
    q = mirror.permutation(
        segments, [rules["far"] for rules in all_rules], colloc.points, assembler.offsets, s
    )
    if q is not None and any(
        with_g[k] != with_g[colloc.segment[q[starts[k]]]] for k in range(len(segments))
    ):
        q = None  # G's columns left out on one side only
    integrated = None if q is None else mirror.integrated_rows(q, colloc.points)
    filled = None if q is None else mirror.Fill(q, integrated)  # H and G, twice
    jobs, stored, integrated_any = [], [], False
    for k, basis in enumerate(segments):
        columns = slice(2 * assembler.offsets[k], 2 * assembler.offsets[k + 1])
        key = (shear_modulus, nu, s, loops.__name__, with_g[k], q is not None)
        known = {
            r: block
            for r, row_basis in enumerate(segments)
            if reuse and (block := BLOCKS.get(basis, row_basis, key)) is not None
        }
        todo = _rows_outside(starts, known)
        if integrated is not None:
            todo = todo[integrated[todo]]
        rows = np.arange(starts[k], starts[k + 1])
        rules = all_rules[k]
        cols = assembler.offsets[k] + basis.connectivity
        if todo.size:  # rows whose blocks no earlier body (or its point image) holds
            integrated_any = True
            pr, pe, kind = loops.classify_and_integrate(
                todo, colloc.points, colloc.segment == k, colloc.parameter,
                basis.element_bounds, rules["samples"], rules["centres"], rules["radii"],
                rules["length"], *rules["far"], *rules["mid"], cols, s.far_ratio,
                s.near_ratio, shear_modulus, nu, h, g, *(() if with_g[k] else (False,)),
            )  # fmt: skip
            near = kind == loops.NEAR
            pr, pe = todo[pr[near]], pe[near]
            if pr.size:
                _near(loops, basis, rules, colloc.points, pr, pe, cols, s, (shear_modulus, nu),
                      h, g, with_g[k])  # fmt: skip
        for r in range(len(segments)):
            block_rows = slice(2 * starts[r], 2 * starts[r + 1])
            if r in known:
                h[block_rows, columns], g[block_rows, columns] = known[r]
            elif keeps_blocks:
                stored.append((basis, segments[r], key, block_rows, columns))
        jobs.append(
            (k, basis, rows, rules["values"], rows[rules["singular_rows"]],
             rules["singular_elements"], rules["singular_sides"], with_g[k])
        )  # fmt: skip
    if q is not None and integrated_any and stored:  # the rows not integrated, from their
        # mirrors, for the blocks kept (each whole row is filled again at the end: a body
        # that keeps no blocks skips this pass, 481 pairs 2-4 ms, the same numbers)
        filled(h)
        filled(g)
    for basis, row_basis, key, block_rows, columns in stored:
        BLOCKS.put(basis, row_basis, key, h[block_rows, columns], g[block_rows, columns])
    if reuse:
        BLOCKS.assembled(segments, lent=n > REUSE_MAX_FUNCTIONS)
    # rigid-body identity: subtract phi_a(s) * (row sum of the non-singular part of H)
    # (a mirrored body: the integrated rows' sums only, each row's sum the same arithmetic)
    row_sums = _rigid_row_sums(loops, h, n, integrated)
    for k, basis, rows, values, *_ in jobs:
        if integrated is not None:  # the other rows of a mirrored body: filled below
            on = integrated[rows]
            rows, values = rows[on], values[on]
        cols = assembler.offsets[k] + basis.connectivity[colloc.element[rows]]
        blocks = -np.einsum("pa,pij->piaj", values, row_sums[rows])
        loops.scatter_blocks(rows, cols, np.ascontiguousarray(blocks), h)
    for k, basis, _, _, rows, elements, singular, with_g in jobs:
        if integrated is not None:
            on = integrated[rows]
            rows = rows[on]
            elements, singular = _integrated_singular(basis, s, on, elements, singular)
        if not rows.size:
            continue
        if integrated is None:
            singular = singular.arrays()
        cols = assembler.offsets[k] + basis.connectivity[elements]
        # both sides of every split element in one call: the pairs of side -1, then side +1
        loops.integrate_singular(
            np.concatenate([rows, rows]), colloc.points, *singular,
            np.concatenate([cols, cols]), shear_modulus, nu, h, g, *(() if with_g else (False,)),
        )  # fmt: skip
    if integrated is not None:  # the mirrored rows whole, their singular terms included
        filled(h)
        filled(g)
    return h, g
