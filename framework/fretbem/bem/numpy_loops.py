"""The loops of :mod:`fretbem.bem.compiled_loops` written with numpy, for processes without numba.

Same signatures, classes and formulas (:mod:`fretbem.bem.assembly` runs on either): pairs
are classified by whole arrays; the far field, most of the pairs, is evaluated on dense
(elements, points, rows) blocks with the non-far pairs masked out after the sum over the
points (in numpy that beats gathering them) and added into H and G through strided views;
mid, near and singular pairs are gathered and scattered in place with ``np.add.at``.
Every kernel operation runs along a long contiguous axis into reused scratch arrays
(:func:`_scratch`): short inner loops and freshly touched pages, not the arithmetic, were
what the numpy loops spent their time on.
"""

from __future__ import annotations

import math
import threading

import numpy as np

FAR, MID, NEAR, SINGULAR = 0, 1, 2, 3
#: the loops can leave G's columns of chosen segments out (``with_g=False``; the compiled
#: loops integrate both always)
SKIPS_G = True

#: kernel evaluations per chunk of per-pair rules (64 kB per temporary)
CHUNK = 8192
#: points of a per-pair rule up to which its sum runs as a loop over the points (each step
#: along the pairs); longer rules (the near pairs' graded ones) sum in one einsum
SUM_LOOP_POINTS = 32
#: kernel evaluations per far-field block of rows (64 kB per temporary: they stay in cache
#: and below the allocator's threshold for fresh pages)
FAR_BLOCK = 32768


_SCRATCH = threading.local()


def _scratch(*shapes: tuple[int, ...]) -> list[np.ndarray]:
    """Uninitialised float64 arrays of ``shapes``, views of this thread's scratch buffer.

    The buffer is kept between calls and only grows (to ``FAR_BLOCK`` and ``CHUNK`` sized
    blocks, a few MB): pages written for the first time cost their faults, about 20x the
    arithmetic of the kernel written into them. The arrays are valid until the next call.
    """
    sizes = [math.prod(shape) for shape in shapes]
    buffer = getattr(_SCRATCH, "buffer", None)
    if buffer is None or buffer.size < sum(sizes):
        buffer = _SCRATCH.buffer = np.empty(sum(sizes))
    out, start = [], 0
    for size, shape in zip(sizes, shapes, strict=True):
        out.append(buffer[start : start + size].reshape(shape))
        start += size
    return out


def scatter_blocks(rows, cols, blocks, matrix):
    """matrix[2 rows[p] + i, 2 cols[p, a] + j] += blocks[p, i, a, j], in place."""
    index = _flat_index(rows, cols, matrix.shape[1])
    np.add.at(matrix.reshape(-1), index, blocks.ravel())


def _scatter_both(rows, cols, blocks, h, g):
    """``scatter_blocks`` of blocks[0] into H and blocks[1] into G (one index for both)."""
    index = _flat_index(rows, cols, h.shape[1])
    np.add.at(h.reshape(-1), index, blocks[0].ravel())
    np.add.at(g.reshape(-1), index, blocks[1].ravel())


def _flat_index(rows, cols, width: int) -> np.ndarray:
    """Flat indices (2 rows[p] + i) width + 2 cols[p, a] + j, ordered [p, i, a, j]."""
    base = (2 * width) * rows[:, None] + 2 * cols  # (p, a): the corner i = j = 0
    out = np.empty((len(rows), 2, base.shape[1], 2), dtype=base.dtype)
    for i in range(2):
        for j in range(2):
            np.add(base, i * width + j, out=out[:, i, :, j])
    return out.ravel()


class _Kernel:
    """The constants of the Kelvin kernel's seven distinct weighted components (T, and U,
    which is symmetric), in the formulas of :func:`~fretbem.bem.kernels.traction_and_displacement`.
    """

    def __init__(self, shear_modulus: float, nu: float):
        self.a = 1.0 - 2.0 * nu
        self.t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
        self.u_scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
        self.log_coef = -(3.0 - 4.0 * nu) * 0.5

    def components(self, rx, ry, nx, ny, tw, uw, out, log_term=None, work=None) -> None:
        """Write T00, T01, T10, T11, U00, U01, U11 times the weights into ``out[0..6]``
        (T's four alone when ``out`` has four entries: G not wanted).

        ``rx, ry``: field point minus source; ``nx, ny``: the field point's normal; ``tw, uw``:
        the weight times t_scale and u_scale; all broadcast to the shape of each ``out[k]``.
        ``log_term`` replaces U's (3 - 4 nu) ln(1/r) (the singular rules split it).
        ``work``: eight scratch arrays of that shape (allocated if None); every operation
        writes into them or into ``out``, so no temporary is allocated (fresh arrays of a few
        hundred kB cost their page faults, 20x the arithmetic).
        """
        a = self.a
        if work is None:
            work = np.empty((8, *out[0].shape))
        rxx, ryy, rxy, d2, inv, dr_dn, skew, tmp = work
        np.multiply(rx, rx, out=rxx)
        np.multiply(ry, ry, out=ryy)
        np.multiply(rx, ry, out=rxy)
        np.add(rxx, ryy, out=d2)
        np.divide(1.0, d2, out=inv)
        ux = np.multiply(rxx, inv, out=rxx)
        uy = np.multiply(ryy, inv, out=ryy)
        uxy = np.multiply(rxy, inv, out=rxy)
        with_g = len(out) > 4
        if log_term is None and with_g:
            log_term = np.log(d2, out=d2)
            log_term *= self.log_coef  # (3 - 4 nu) ln(1/r)
        scale = np.multiply(tw, inv, out=inv)
        np.multiply(rx, nx, out=dr_dn)
        dr_dn += np.multiply(ry, ny, out=tmp)
        dr_dn *= scale  # t_scale w (dr/dn) / r
        np.multiply(rx, ny, out=skew)
        skew -= np.multiply(ry, nx, out=tmp)
        skew *= scale
        skew *= a  # t_scale w (1 - 2 nu)(r_x n_y - r_y n_x) / r^2
        two = np.multiply(dr_dn, 2.0, out=tmp)
        a_dr_dn = np.multiply(dr_dn, a, out=dr_dn)
        np.multiply(two, ux, out=out[0])
        out[0] += a_dr_dn  # T00 = dr_dn (a + 2 ux)
        np.multiply(two, uxy, out=out[1])
        np.add(out[1], skew, out=out[2])  # T10
        out[1] -= skew  # T01
        np.multiply(two, uy, out=out[3])
        out[3] += a_dr_dn  # T11
        if not with_g:
            return
        np.add(log_term, ux, out=out[4])
        out[4] *= uw  # U00
        np.multiply(uw, uxy, out=out[5])  # U01 = U10
        np.add(log_term, uy, out=out[6])
        out[6] *= uw  # U11


#: (matrix, i, j) of the seven kernel components, in their order (U_10 = U_01)
COMPONENTS = ((0, 0, 0), (0, 0, 1), (0, 1, 0), (0, 1, 1), (1, 0, 0), (1, 0, 1), (1, 1, 1))


def _integrate(sources, x, n, jw, phi, rows, cols, shear_modulus, nu, h, g, with_g=True):
    """Per-pair rules (pair p: points x[p], J w jw[p], values phi[p]) into H and G (H alone
    unless ``with_g``)."""
    kernel = _Kernel(shear_modulus, nu)
    n_q, n_loc = phi.shape[1], phi.shape[2]
    n_k = 7 if with_g else 4
    chunk = max(1, CHUNK // n_q)
    for start in range(0, len(rows), chunk):
        part = slice(start, start + chunk)
        src, xp, np_, jp = sources[part], x[part], n[part], jw[part]
        count = len(src)
        # every array [point, pair] (pairs along the rows): each operation runs along them
        k, work, phi_t, summed, term = _scratch(
            (n_k, n_q, count), (12, n_q, count), (n_q, n_loc, count), (n_k, n_loc, count),
            (n_k, n_loc, count),
        )  # fmt: skip
        rx = np.subtract(xp[..., 0].T, src[:, 0], out=work[8])
        ry = np.subtract(xp[..., 1].T, src[:, 1], out=work[9])
        tw = np.multiply(kernel.t_scale, jp.T, out=work[10])
        uw = np.multiply(kernel.u_scale, jp.T, out=work[11])
        kernel.components(rx, ry, np_[..., 0].T, np_[..., 1].T, tw, uw, k, work=work[:8])
        # the sum over the points in their order, as einsum adds them (a batched matrix
        # product would be faster, but its sums may differ in the last bit with the pair's
        # place in the batch, and blocks reused between bodies must equal a fresh assembly's
        # exactly: tests/framework/bem/test_block_reuse.py)
        if n_q <= SUM_LOOP_POINTS:  # the mid rules: a loop over the points
            phi_t[...] = phi[part].transpose(1, 2, 0)
            np.multiply(k[:, 0, None], phi_t[0], out=summed)  # [component, a, pair]
            for q in range(1, n_q):
                summed += np.multiply(k[:, q, None], phi_t[q], out=term)
        else:  # the graded near rules (10 points a level): few pairs, many points
            np.einsum("kqp,pqa->kap", k, phi[part], out=summed)
        blocks = np.empty((2 if with_g else 1, count, 2, n_loc, 2))  # [H or G, pair, i, a, j]
        for index, (m, i, j) in enumerate(COMPONENTS[:n_k]):
            blocks[m, :, i, :, j] = summed[index].T
        if not with_g:
            scatter_blocks(rows[part], cols[part], blocks[0], h)
            continue
        blocks[1, :, 1, :, 0] = summed[5].T
        _scatter_both(rows[part], cols[part], blocks, h, g)


def _far_field(src, rows, is_far, x, n, jw, phi, cols, shear_modulus, nu, h, g, with_g=True):
    """Far pairs on dense (elements, points, rows) blocks; non-far pairs masked out after the
    sum over the points.

    The kernel's seven weighted components (``_Kernel``) are written into one
    (elements, points, 7, rows) array, rows last so that every ufunc runs along rows
    (the element's point data broadcast as scalars there), and summed against the
    functions by one batched matrix product per block of rows; each block is added into
    H and into G by one strided add per local function. Blocks hold about ``FAR_BLOCK``
    kernel evaluations.
    """
    kernel = _Kernel(shear_modulus, nu)
    n_el, n_q, n_loc = phi.shape
    n_k = 7 if with_g else 4  # the kernel components: T's alone when G is not wanted
    n_cols = h.shape[1] // 2
    xx, xy = x[:, :, 0, None], x[:, :, 1, None]  # (e, q, 1)
    nx, ny = n[:, :, 0, None], n[:, :, 1, None]
    tw, uw = (kernel.t_scale * jw)[:, :, None], (kernel.u_scale * jw)[:, :, None]
    phi_t = np.ascontiguousarray(phi.transpose(0, 2, 1))  # (e, a, q)
    columns = [_progression(cols[:, b]) for b in range(n_loc)]
    block = max(16, FAR_BLOCK // max(n_el * n_q, 1))
    h_view, g_view = h.reshape(-1, 2, n_cols, 2), g.reshape(-1, 2, n_cols, 2)
    for start in range(0, len(rows), block):
        part = slice(start, start + block)
        r = rows[part]
        c = len(r)
        k, work, summed, by_row = _scratch(
            (n_el, n_q, n_k, c), (10, n_el, n_q, c), (n_el, n_loc, n_k * c),
            (n_loc, n_k, c, n_el),
        )  # fmt: skip
        rx = np.subtract(xx, src[part, 0], out=work[8])  # (e, q, c)
        ry = np.subtract(xy, src[part, 1], out=work[9])
        kernel.components(rx, ry, nx, ny, tw, uw, k.transpose(2, 0, 1, 3), work=work[:8])
        np.matmul(phi_t, k.reshape(n_el, n_q, n_k * c), out=summed)
        # [b, component, row, element], the non-far pairs masked out: every add below then
        # runs along the elements, as H's and G's columns do
        np.multiply(summed.reshape(n_el, n_loc, n_k, c).transpose(1, 2, 3, 0), is_far[part],
                    out=by_row)  # fmt: skip
        rows_at = _progression(r)
        for b in range(n_loc):
            at = columns[b]
            if rows_at is not None and at is not None:
                for index, (m, i, j) in enumerate(COMPONENTS[:n_k]):
                    (h_view, g_view)[m][rows_at, i, at, j] += by_row[b, index]
                if with_g:
                    g_view[rows_at, 1, at, 0] += by_row[b, 5]
            else:
                blocks = np.empty((2, c, 2, n_el, 2))  # [H or G, row, i, element, j]
                for index, (m, i, j) in enumerate(COMPONENTS[:n_k]):
                    blocks[m, :, i, :, j] = by_row[b, index]
                index = (r[:, None, None, None], np.arange(2)[:, None, None],
                         cols[:, b][:, None], np.arange(2))  # fmt: skip
                np.add.at(h_view, index, blocks[0])
                if with_g:
                    blocks[1, :, 1, :, 0] = blocks[1, :, 0, :, 1]
                    np.add.at(g_view, index, blocks[1])


def _distance(dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """sqrt(dx^2 + dy^2) in place of dx, as ``np.linalg.norm`` over the pair's last axis."""
    dx *= dx
    dx += dy * dy
    return np.sqrt(dx, out=dx)


def _progression(index: np.ndarray) -> slice | None:
    """``index`` as a slice if it is an increasing arithmetic progression (else None)."""
    if index.size == 1:
        return slice(int(index[0]), int(index[0]) + 1)
    step = int(index[1] - index[0])
    if step <= 0 or np.any(np.diff(index) != step):
        return None
    return slice(int(index[0]), int(index[-1]) + 1, step)


def classify_and_integrate(
    rows, points, own, parameters, bounds, samples, centres, radii, length,
    far_x, far_n, far_jw, far_phi, mid_x, mid_n, mid_jw, mid_phi, cols,
    far_ratio, near_ratio, shear_modulus, nu, h, g, with_g=True,
):  # fmt: skip
    """Classify every (row, element) pair; integrate far and mid pairs (see _compiled); G's
    terms only ``with_g`` (the compiled loops always integrate both)."""
    src = points[rows]
    lower = _distance(src[:, 0, None] - centres[:, 0], src[:, 1, None] - centres[:, 1])
    lower -= radii
    ratio = lower * (1.0 - 1e-12) / length[None]
    pr, pe = np.nonzero(ratio < far_ratio)
    # distances to the 9 samples (pair, sample), their minimum taken sample by sample
    to_samples = _distance(
        src[pr, 0, None] - samples[pe, :, 0], src[pr, 1, None] - samples[pe, :, 1]
    ).T
    dist = to_samples[0].copy()
    for row in to_samples[1:]:
        np.minimum(dist, row, out=dist)
    exact = dist / length[pe]
    ratio[pr, pe] = np.where(exact >= far_ratio, far_ratio, exact)
    par = parameters[rows][:, None]
    singular = own[rows][:, None] & (par >= bounds[:, 0] - 1e-12) & (par <= bounds[:, 1] + 1e-12)
    kind = np.select(
        [singular, ratio >= far_ratio, ratio >= near_ratio], [SINGULAR, FAR, MID], NEAR
    )
    _far_field(
        src, rows, kind == FAR, far_x, far_n, far_jw, far_phi, cols, shear_modulus, nu, h, g,
        with_g,
    )  # fmt: skip
    pr, pe = np.nonzero(kind == MID)
    data = (mid_x[pe], mid_n[pe], mid_jw[pe], mid_phi[pe])
    _integrate(src[pr], *data, rows[pr], cols[pe], shear_modulus, nu, h, g, with_g)
    pr, pe = np.nonzero(kind >= NEAR)
    return pr, pe, kind[pr, pe]


def integrate_pairs(rows, points, x, n, jw, phi, cols, shear_modulus, nu, h, g, with_g=True):
    """Per-pair rules into H and G rows 2 rows[p] + i (see _compiled.integrate_pairs)."""
    _integrate(points[rows], x, n, jw, phi, rows, cols, shear_modulus, nu, h, g, with_g)


def integrate_singular(
    rows, points, x, n, jw, phi, at_source, t, safe, log_jw, log_phi, cols, shear_modulus, nu,
    h, g, with_g=True,
):  # fmt: skip
    """Elements split at their collocation point, pair by pair (see _compiled): H by singularity
    subtraction, G's ln(1/r) as ln(t / r) - ln(side length) on the Gauss rule plus the
    log-weighted rule."""
    kernel = _Kernel(shear_modulus, nu)
    src = points[rows]
    rx, ry = x[..., 0] - src[:, 0, None], x[..., 1] - src[:, 1, None]
    log_term = None
    if with_g:
        log_term = np.log(np.sqrt(rx * rx + ry * ry) / t)
        log_term += np.log(safe)[:, None]
        log_term *= -(3.0 - 4.0 * nu)  # (3 - 4 nu) ln(1/r), its ln(1/t) part on the log rule
    k = np.empty((len(rows), 7 if with_g else 4, x.shape[1]))
    kernel.components(rx, ry, n[..., 0], n[..., 1], kernel.t_scale * jw, kernel.u_scale * jw,
                      k.transpose(1, 0, 2), log_term=log_term)  # fmt: skip
    h_sums = np.einsum("pkq,pqa->pka", k[:, :4], phi - at_source[:, None, :])
    if not with_g:
        blocks = np.empty((len(rows), 2, phi.shape[2], 2))  # [pair, i, a, j]
        for index, (_, i, j) in enumerate(COMPONENTS[:4]):
            blocks[:, i, :, j] = h_sums[:, index]
        scatter_blocks(rows, cols, blocks, h)
        return
    g_sums = np.einsum("pkq,pqa->pka", k[:, 4:], phi)
    log_sums = (kernel.u_scale * (3.0 - 4.0 * nu)) * np.einsum("pq,pqa->pa", log_jw, log_phi)
    blocks = np.empty((2, len(rows), 2, phi.shape[2], 2))  # [H or G, pair, i, a, j]
    for index, (m, i, j) in enumerate(COMPONENTS):
        blocks[m, :, i, :, j] = (h_sums if m == 0 else g_sums)[:, index - 4 * m]
    blocks[1, :, 1, :, 0] = g_sums[:, 1]
    blocks[1, :, 0, :, 0] += log_sums
    blocks[1, :, 1, :, 1] += log_sums
    _scatter_both(rows, cols, blocks, h, g)
