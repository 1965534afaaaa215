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

import numpy as np

from fretbem.numerics.graded import graded_rule
from fretbem.numerics.quadrature import QuadratureRule

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


def assemble(assembler, shear_modulus: float, nu: float, loops) -> tuple[np.ndarray, np.ndarray]:
    """Dense H and G of ``assembler`` (an :class:`~fretbem.bem.integration.Assembler`).

    ``loops`` is :mod:`fretbem.bem.compiled_loops` or :mod:`fretbem.bem.numpy_loops`.
    """
    n, s, colloc = assembler.n, assembler.settings, assembler.colloc
    h, g = np.zeros((2 * n, 2 * n)), np.zeros((2 * n, 2 * n))
    far_rule = QuadratureRule.gauss_legendre(s.far_points)
    mid_rule = QuadratureRule.gauss_legendre(s.mid_points)
    per_element = np.concatenate([far_rule.points, mid_rule.points, START])
    cut = np.cumsum([0, far_rule.points.size, mid_rule.points.size, START.size])
    all_rows = np.arange(n)
    jobs = []
    for k, basis in enumerate(assembler.segments):
        n_el = basis.n_elements
        rows = np.flatnonzero(colloc.segment == k)
        # singular pairs depend only on parameters: the element(s) holding each point
        lo, hi = basis.element_bounds.T
        params = colloc.parameter[rows][:, None]
        sr, se = np.nonzero((params >= lo - 1e-12) & (params <= hi + 1e-12))
        lo_s, hi_s = basis.element_bounds[se].T
        center = np.clip(2.0 * (colloc.parameter[rows[sr]] - lo_s) / (hi_s - lo_s) - 1.0, -1, 1)
        sides = _singular_rules(center, s)
        singular_local = np.concatenate(
            [center[:, None]] + [np.concatenate([d["local"], d["log_local"]], 1) for d in sides],
            axis=1,
        )
        q_sing = singular_local.shape[1]
        m = basis.map(
            np.concatenate(
                [
                    np.repeat(np.arange(n_el), per_element.size),
                    colloc.element[rows],
                    np.repeat(se, q_sing),
                ]
            ),
            np.concatenate(
                [np.tile(per_element, n_el), colloc.local[rows], singular_local.ravel()]
            ),
        )
        a0 = n_el * per_element.size
        a1 = a0 + rows.size

        def per_el(array, part, a0=a0, n_el=n_el):
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
        length = mid[2].sum(axis=1)
        centres = 0.5 * (samples.max(axis=1) + samples.min(axis=1))
        radii = np.linalg.norm(samples - centres[:, None], axis=-1).max(axis=1)
        cols = assembler.offsets[k] + basis.connectivity
        pr, pe, kind = loops.classify_and_integrate(
            all_rows, colloc.points, colloc.segment == k, colloc.parameter,
            basis.element_bounds, samples, centres, radii, length, *far, *mid, cols,
            s.far_ratio, s.near_ratio, shear_modulus, nu, h, g,
        )  # fmt: skip
        near = kind == loops.NEAR
        pr, pe = pr[near], pe[near]
        if pr.size:
            src = colloc.points[pr]
            center_near, distance = _closest(
                basis, pe, src, per_el(m.points, 2), per_el(m.tangents, 2)
            )
            local, weights = graded_rule(
                center_near, 2.0 * distance / length[pe], s.graded_points, s.graded_ratio
            )
            near_map = basis.map(np.repeat(pe, local.shape[1]), local.ravel())
            shape = local.shape
            loops.integrate_pairs(
                pr, colloc.points, near_map.points.reshape(*shape, 2),
                near_map.normals.reshape(*shape, 2), near_map.jacobians.reshape(shape) * weights,
                near_map.values.reshape(*shape, -1), cols[pe], shear_modulus, nu, h, g,
            )  # fmt: skip
        singular = {
            key: getattr(m, key)[a1:].reshape(len(se), q_sing, *getattr(m, key).shape[1:])
            for key in ("points", "normals", "jacobians", "values")
        }
        jobs.append((k, basis, rows, m.values[a0:a1], rows[sr], se, sides, singular))
    # rigid-body identity: subtract phi_a(s) * (row sum of the non-singular part of H)
    row_sums = h.reshape(n, 2, n, 2).sum(axis=2)
    for k, basis, rows, values, *_ in jobs:
        cols = assembler.offsets[k] + basis.connectivity[colloc.element[rows]]
        blocks = -np.einsum("pa,pij->piaj", values, row_sums[rows])
        loops.scatter_blocks(rows, cols, np.ascontiguousarray(blocks), h)
    q_gauss, q_log = s.singular_points, s.log_points
    for k, basis, _, _, rows, elements, sides, data in jobs:
        if not rows.size:
            continue
        cols = assembler.offsets[k] + basis.connectivity[elements]
        at_source = np.ascontiguousarray(data["values"][:, 0])
        start = 1
        for side in sides:
            gauss = slice(start, start + q_gauss)
            log = slice(start + q_gauss, start + q_gauss + q_log)
            start += q_gauss + q_log
            loops.integrate_singular(
                rows, colloc.points, *_contiguous(data["points"][:, gauss],
                data["normals"][:, gauss]), data["jacobians"][:, gauss] * side["weights"],
                np.ascontiguousarray(data["values"][:, gauss]), at_source, side["t"],
                side["safe"], data["jacobians"][:, log] * side["log_weights"],
                np.ascontiguousarray(data["values"][:, log]), cols, shear_modulus, nu,
                h, g,
            )  # fmt: skip
    return h, g
