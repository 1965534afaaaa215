"""The loops of :mod:`fretbem.bem.compiled_loops` written with numpy, for processes without numba.

Same signatures, classes and formulas (:mod:`fretbem.bem.assembly` runs on either): pairs
are classified by whole arrays; the far field, most of the pairs, is evaluated on dense
(rows, elements, points) blocks with the non-far pairs' weights zeroed (in numpy that beats
gathering them) and added into H and G column by column; mid, near and singular pairs are
gathered and scattered in place with ``np.add.at``.
"""

from __future__ import annotations

import numpy as np

from . import kernels

FAR, MID, NEAR, SINGULAR = 0, 1, 2, 3

#: pairs integrated per chunk (bounds the (pairs, points, 2, 2) kernel temporaries)
CHUNK = 8192
#: kernel evaluations per far-field block (about 13 MB per kernel array)
FAR_BLOCK = 200_000


def scatter_blocks(rows, cols, blocks, matrix):
    """matrix[2 rows[p] + i, 2 cols[p, a] + j] += blocks[p, i, a, j], in place."""
    i = np.arange(2)
    r = 2 * rows[:, None, None, None] + i[None, :, None, None]
    c = 2 * cols[:, None, :, None] + i[None, None, None, :]
    np.add.at(matrix.reshape(-1), (r * matrix.shape[1] + c).ravel(), blocks.ravel())


def _integrate(sources, x, n, jw, phi, rows, cols, shear_modulus, nu, h, g):
    """Per-pair rules (pair p: points x[p], J w jw[p], values phi[p]) into H and G."""
    for start in range(0, len(rows), CHUNK):
        part = slice(start, start + CHUNK)
        t, u = kernels.traction_and_displacement(
            sources[part, None, :], x[part], n[part], shear_modulus=shear_modulus, nu=nu
        )
        weighted = jw[part, :, None] * phi[part]
        scatter_blocks(rows[part], cols[part], np.einsum("pqij,pqa->piaj", t, weighted), h)
        scatter_blocks(rows[part], cols[part], np.einsum("pqij,pqa->piaj", u, weighted), g)


def _far_field(src, rows, is_far, x, n, jw, phi, cols, shear_modulus, nu, h, g):
    """Far pairs on dense (rows, elements, points) blocks, non-far weights zero."""
    n_cols = h.shape[1] // 2
    distinct = all(np.unique(cols[:, a]).size == cols.shape[0] for a in range(cols.shape[1]))
    block = max(1, FAR_BLOCK // max(x.shape[0] * x.shape[1], 1))
    for start in range(0, len(rows), block):
        part = slice(start, start + block)
        t, u = kernels.traction_and_displacement(
            src[part, None, None, :], x[None], n[None], shear_modulus=shear_modulus, nu=nu
        )
        weight = jw[None] * is_far[part, :, None]
        r = rows[part]
        for kernel, target in ((t, h), (u, g)):
            blocks = np.einsum("ceqij,ceq,eqa->ciaej", kernel, weight, phi, optimize=True)
            view = target.reshape(-1, 2, n_cols, 2)
            for a in range(cols.shape[1]):
                if distinct and np.all(np.diff(r) == 1):
                    view[r[0] : r[-1] + 1, :, cols[:, a], :] += blocks[:, :, a]
                else:
                    index = (
                        r[:, None, None, None],
                        np.arange(2)[:, None, None],
                        cols[:, a][:, None],
                        np.arange(2),
                    )
                    np.add.at(view, index, blocks[:, :, a])


def classify_and_integrate(
    rows, points, own, parameters, bounds, samples, centres, radii, length,
    far_x, far_n, far_jw, far_phi, mid_x, mid_n, mid_jw, mid_phi, cols,
    far_ratio, near_ratio, shear_modulus, nu, h, g,
):  # fmt: skip
    """Classify every (row, element) pair; integrate far and mid pairs (see _compiled)."""
    src = points[rows]
    lower = np.linalg.norm(src[:, None, :] - centres[None], axis=-1) - radii[None]
    ratio = lower * (1.0 - 1e-12) / length[None]
    pr, pe = np.nonzero(ratio < far_ratio)
    dist = np.linalg.norm(src[pr, None, :] - samples[pe], axis=-1).min(axis=1)
    exact = dist / length[pe]
    ratio[pr, pe] = np.where(exact >= far_ratio, far_ratio, exact)
    par = parameters[rows][:, None]
    singular = own[rows][:, None] & (par >= bounds[:, 0] - 1e-12) & (par <= bounds[:, 1] + 1e-12)
    kind = np.select(
        [singular, ratio >= far_ratio, ratio >= near_ratio], [SINGULAR, FAR, MID], NEAR
    )
    _far_field(src, rows, kind == FAR, far_x, far_n, far_jw, far_phi, cols, shear_modulus, nu, h, g)
    pr, pe = np.nonzero(kind == MID)
    data = (mid_x[pe], mid_n[pe], mid_jw[pe], mid_phi[pe])
    _integrate(src[pr], *data, rows[pr], cols[pe], shear_modulus, nu, h, g)
    pr, pe = np.nonzero(kind >= NEAR)
    return pr, pe, kind[pr, pe]


def integrate_pairs(rows, points, x, n, jw, phi, cols, shear_modulus, nu, h, g):
    """Per-pair rules into H and G rows 2 rows[p] + i (see _compiled.integrate_pairs)."""
    _integrate(points[rows], x, n, jw, phi, rows, cols, shear_modulus, nu, h, g)


def integrate_singular(
    rows, points, x, n, jw, phi, at_source, t, safe, log_jw, log_phi, cols, shear_modulus, nu,
    h, g,
):  # fmt: skip
    """One side of elements split at their collocation point (see _compiled)."""
    src = points[rows][:, None, :]
    t_kernel = kernels.traction(src, x, n, nu=nu)
    h_blocks = np.einsum("pqij,pq,pqa->piaj", t_kernel, jw, phi - at_source[:, None, :])
    scatter_blocks(rows, cols, h_blocks, h)
    log_coef, smooth = kernels.displacement_parts(src, x, shear_modulus=shear_modulus, nu=nu)
    dist = np.linalg.norm(x - src, axis=-1)
    log_factor = -np.log(dist / t) - np.log(safe)[:, None]
    kernel = smooth + (log_coef * log_factor)[..., None, None] * np.eye(2)
    g_blocks = np.einsum("pqij,pq,pqa->piaj", kernel, jw, phi)
    g_blocks += log_coef * np.einsum("pq,pqa,ij->piaj", log_jw, log_phi, np.eye(2))
    scatter_blocks(rows, cols, g_blocks, g)
