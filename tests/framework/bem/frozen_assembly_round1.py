"""Frozen copy of the round-1 collocation assembler (commit d148f93), the reference the
compiled assembler is tested against (tests/framework/test_assembly_compiled.py).

Verbatim copies of fretbem/bem/integration.py and fretbem/bem/kernels.py as they were before the
compiled kernels; only the imports are adjusted. Do not edit: it pins the numbers.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np
import scipy.sparse as sp

from fretbem.basis import Basis
from fretbem.numerics.quadrature import QuadratureRule

# -- kernels (fretbem/bem/kernels.py) --
IDENTITY = np.eye(2)


def _offsets(source: np.ndarray, field: np.ndarray):
    r = field - source
    dist = np.linalg.norm(r, axis=-1)
    return r / dist[..., None], dist


def displacement(source, field, *, shear_modulus: float, nu: float) -> np.ndarray:
    """U_ij: displacement kernel, C [(3 - 4 nu) ln(1/r) delta_ij + r_i r_j]."""
    unit, dist = _offsets(source, field)
    scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_term = (-(3.0 - 4.0 * nu) * np.log(dist))[..., None, None] * IDENTITY
    return scale * (log_term + unit[..., :, None] * unit[..., None, :])


def displacement_parts(source, field, *, shear_modulus: float, nu: float):
    """U split as (coefficient of ln(1/r) delta_ij, smooth remainder r_i r_j): for log rules."""
    unit, _ = _offsets(source, field)
    scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    return scale * (3.0 - 4.0 * nu), scale * unit[..., :, None] * unit[..., None, :]


def traction(source, field, normal, *, nu: float) -> np.ndarray:
    """T_ij: traction kernel on the surface with outward ``normal`` at ``field``."""
    unit, dist = _offsets(source, field)
    dr_dn = np.sum(unit * normal, axis=-1)
    scale = -1.0 / (4.0 * np.pi * (1.0 - nu) * dist)
    outer = unit[..., :, None] * unit[..., None, :]
    normal_part = dr_dn[..., None, None] * ((1.0 - 2.0 * nu) * IDENTITY + 2.0 * outer)
    skew = unit[..., :, None] * normal[..., None, :] - normal[..., :, None] * unit[..., None, :]
    return scale[..., None, None] * (normal_part - (1.0 - 2.0 * nu) * skew)


def traction_and_displacement(source, field, normal, *, shear_modulus: float, nu: float):
    """T and U together from one pass over the offsets (the far-field hot loop).

    Same formulas as :func:`traction` and :func:`displacement`, written per component to
    avoid the (..., 2, 2) temporaries; about twice as fast on large blocks.
    """
    rx, ry = field[..., 0] - source[..., 0], field[..., 1] - source[..., 1]
    d2 = rx * rx + ry * ry
    inv = 1.0 / d2
    ux, uy = rx * rx * inv, ry * ry * inv  # r_i r_j / r^2 terms
    uxy = rx * ry * inv
    nx, ny = normal[..., 0], normal[..., 1]
    dr_dn = (rx * nx + ry * ny) * inv  # (dr/dn) / r
    a = 1.0 - 2.0 * nu
    t_scale = -1.0 / (4.0 * np.pi * (1.0 - nu))
    skew = a * (rx * ny - ry * nx) * inv  # (1 - 2 nu)(r_x n_y - r_y n_x) / r^2
    t = np.empty((*d2.shape, 2, 2))
    t[..., 0, 0] = t_scale * dr_dn * (a + 2.0 * ux)
    t[..., 1, 1] = t_scale * dr_dn * (a + 2.0 * uy)
    t[..., 0, 1] = t_scale * (dr_dn * 2.0 * uxy - skew)
    t[..., 1, 0] = t_scale * (dr_dn * 2.0 * uxy + skew)
    u_scale = 1.0 / (8.0 * np.pi * shear_modulus * (1.0 - nu))
    log_term = -(3.0 - 4.0 * nu) * 0.5 * np.log(d2)
    u = np.empty_like(t)
    u[..., 0, 0] = u_scale * (log_term + ux)
    u[..., 1, 1] = u_scale * (log_term + uy)
    u[..., 0, 1] = u[..., 1, 0] = u_scale * uxy
    return t, u


# -- assembler (fretbem/bem/integration.py) --


@attrs.frozen
class IntegrationSettings:
    """Quadrature orders and distance thresholds (see module docstring)."""

    far_ratio: float = 4.0
    far_points: int = 6
    near_ratio: float = 0.5
    mid_points: int = 16
    graded_points: int = 10
    graded_ratio: float = 0.5
    singular_points: int = 16
    log_points: int = 8
    block_rows: int = 256


@attrs.frozen(eq=False)
class Collocation:
    """Where a body collocates: per point its segment, element, local coordinate, position.

    Attributes
    ----------
    segment, element : ndarray of int
    local, parameter : ndarray
    points, normals : ndarray, shape (N, 2)
    """

    segment: np.ndarray
    element: np.ndarray
    local: np.ndarray
    parameter: np.ndarray
    points: np.ndarray
    normals: np.ndarray

    @classmethod
    def of(cls, segments: Sequence[Basis]) -> Collocation:
        """Collocation data of the discretised segments, in segment order."""
        parts = []
        for k, basis in enumerate(segments):
            elements, local = basis.collocation()
            points, _, _, normals = basis.geometry(elements, local)
            parts.append(
                (
                    np.full(len(elements), k),
                    elements,
                    local,
                    basis.collocation_parameters,
                    points,
                    normals,
                )
            )
        return cls(*(np.concatenate(column) for column in zip(*parts, strict=True)))


def offsets(segments: Sequence[Basis]) -> np.ndarray:
    """First global function index of every segment, and the total at the end."""
    return np.concatenate([[0], np.cumsum([b.n_functions for b in segments])])


class _Accumulator:
    """Scatter-adds (rows, 2, n_local, 2) blocks into a dense 2N x 2M matrix via bincount."""

    def __init__(self, n_rows: int, n_cols: int):
        self.shape = (2 * n_rows, 2 * n_cols)
        self.flat = np.zeros(self.shape[0] * self.shape[1])

    def add(self, rows: np.ndarray, cols: np.ndarray, blocks: np.ndarray) -> None:
        """blocks[p, i, a, j] goes to (2 rows[p] + i, 2 cols[p, a] + j)."""
        i = np.arange(2)
        r = 2 * rows[:, None, None, None] + i[None, :, None, None]
        c = 2 * cols[:, None, :, None] + i[None, None, None, :]
        index = (r * self.shape[1] + c).ravel()
        self.flat += np.bincount(index, weights=blocks.ravel(), minlength=self.flat.size)

    def matrix(self) -> np.ndarray:
        return self.flat.reshape(self.shape)


def _pairs_quadrature(basis, elements, local, weights):
    """Geometry and shape functions at per-pair points local (P, Q); weights include dlocal."""
    n_pairs, n_points = local.shape
    m = basis.map(np.repeat(elements, n_points), local.ravel())
    shape3 = (n_pairs, n_points)
    return (
        m.points.reshape(*shape3, 2),
        m.normals.reshape(*shape3, 2),
        (m.jacobians.reshape(shape3) * weights),
        m.values.reshape(*shape3, -1),
    )


def _element_rule(basis, rule: QuadratureRule):
    """The same rule on every element: points, normals, J w, values, each (n_el, q, ...)."""
    n_el = basis.n_elements
    local = np.tile(rule.points, (n_el, 1))
    points, normals, jw, values = _pairs_quadrature(basis, np.arange(n_el), local, rule.weights)
    return points, normals, jw, values


def _closest_local(basis, elements, sources, iterations: int = 3):
    """Local coordinate on each element closest to each source (sampling, then Gauss-Newton)."""
    samples = np.linspace(-1.0, 1.0, 17)
    pts, *_ = basis.geometry(np.repeat(elements, samples.size), np.tile(samples, len(elements)))
    dist = np.linalg.norm(pts.reshape(len(elements), samples.size, 2) - sources[:, None], axis=-1)
    eta = samples[np.argmin(dist, axis=1)]
    for _ in range(iterations):
        x, tangent, *_ = basis.geometry(elements, eta)
        step = np.sum((x - sources) * tangent, axis=-1) / np.sum(tangent**2, axis=-1)
        eta = np.clip(eta - step, -1.0, 1.0)
    x, *_ = basis.geometry(elements, eta)
    return eta, np.linalg.norm(x - sources, axis=-1)


def _graded_rule(center, distance_local, settings):
    """Composite Gauss rule on [-1, 1] graded geometrically toward ``center`` on both sides.

    Sub-intervals shrink by ``graded_ratio`` until they are about as small as the distance
    to the singularity (in local units), so every piece sees it at >= its own length.
    """
    sigma = settings.graded_ratio
    base = QuadratureRule.gauss_legendre(settings.graded_points)
    pieces_local, pieces_weight = [], []
    for side in (-1.0, 1.0):
        length = np.where(side < 0, center + 1.0, 1.0 - center)
        need = np.log(np.maximum(distance_local, 1e-14) / np.maximum(length, 1e-300)) / np.log(
            sigma
        )
        levels = np.clip(np.ceil(need) + 1, 1, 60).astype(int)
        m = int(levels.max())
        k = np.minimum(np.arange(m + 1)[None, :], levels[:, None])
        edges = length[:, None] * sigma**k  # decreasing distances from the centre
        edges = np.concatenate([edges, np.zeros((len(center), 1))], axis=1)
        t, w = base.mapped(edges[:, 1:], edges[:, :-1])  # (P, m + 1, n)
        pieces_local.append((center[:, None, None] + side * t).reshape(len(center), -1))
        pieces_weight.append(w.reshape(len(center), -1))
    return np.concatenate(pieces_local, axis=1), np.concatenate(pieces_weight, axis=1)


class Assembler:
    """Builds H and G for a list of discretised segments of one homogeneous body."""

    def __init__(
        self,
        segments: Sequence[Basis],
        shear_modulus: float,
        nu: float,
        settings: IntegrationSettings | None = None,
    ):
        self.segments = tuple(segments)
        self.mu, self.nu = float(shear_modulus), float(nu)
        self.settings = settings or IntegrationSettings()
        self.offsets = offsets(self.segments)
        self.n = int(self.offsets[-1])
        self.colloc = Collocation.of(self.segments)

    # -- kernels times shape functions, contracted over quadrature points ------------------
    def _blocks(self, sources, points, normals, jw, values, *, subtract=None):
        """(P, 2, n_local, 2) blocks of H and G from per-pair quadrature data."""
        src = sources[:, None, :]
        t_kernel = traction(src, points, normals, nu=self.nu)
        u_kernel = displacement(src, points, shear_modulus=self.mu, nu=self.nu)
        phi_h = values if subtract is None else values - subtract[:, None, :]
        h = np.einsum("pqij,pq,pqa->piaj", t_kernel, jw, phi_h, optimize=True)
        g = np.einsum("pqij,pq,pqa->piaj", u_kernel, jw, values, optimize=True)
        return h, g

    def assemble(self) -> tuple[np.ndarray, np.ndarray]:
        """Dense H and G, rows 2 s + i (collocation point s), columns 2 b + j (function b)."""
        n = self.n
        h_acc, g_acc = _Accumulator(n, n), _Accumulator(n, n)
        singular_jobs = []
        for k, basis in enumerate(self.segments):
            self._assemble_segment(k, basis, h_acc, g_acc, singular_jobs)
        h, g = h_acc.matrix(), g_acc.matrix()
        # rigid-body identity: subtract phi_a(s) * (row sum of the non-singular part of H)
        row_sums = h.reshape(n, 2, n, 2).sum(axis=2)  # (s, i, j)
        for k, basis in enumerate(self.segments):
            rows = np.flatnonzero(self.colloc.segment == k)
            values, _ = basis.shape_functions(self.colloc.element[rows], self.colloc.local[rows])
            cols = self.offsets[k] + basis.connectivity[self.colloc.element[rows]]
            h_acc.add(rows, cols, -np.einsum("pa,pij->piaj", values, row_sums[rows]))
        g_sing = _Accumulator(n, n)
        for job in singular_jobs:
            self._singular(*job, h_acc, g_sing)
        return h_acc.matrix(), g + g_sing.matrix()

    def _assemble_segment(self, k, basis, h_acc, g_acc, singular_jobs):
        s = self.settings
        colloc = self.colloc
        n_el, n_loc = basis.n_elements, basis.n_local
        cols_of = self.offsets[k] + basis.connectivity  # (n_el, n_loc)
        # element data for the far rule, element sizes and distance samples
        x_far, n_far, jw_far, phi_far = _element_rule(
            basis, QuadratureRule.gauss_legendre(s.far_points)
        )
        mid_data = _element_rule(basis, QuadratureRule.gauss_legendre(s.mid_points))
        length = mid_data[2].sum(axis=1)
        samples = np.linspace(-1.0, 1.0, 9)
        x_samp, *_ = basis.geometry(np.repeat(np.arange(n_el), 9), np.tile(samples, n_el))
        x_samp = x_samp.reshape(n_el, 9, 2)
        assembly = sp.csr_matrix(
            (np.ones(n_el * n_loc), (np.arange(n_el * n_loc), basis.connectivity.ravel())),
            shape=(n_el * n_loc, basis.n_functions),
        )
        col_slice = slice(2 * self.offsets[k], 2 * self.offsets[k + 1])
        h_mat = h_acc.flat.reshape(h_acc.shape)
        g_mat = g_acc.flat.reshape(g_acc.shape)
        for start in range(0, self.n, s.block_rows):
            rows = np.arange(start, min(start + s.block_rows, self.n))
            src = colloc.points[rows]
            dist = np.linalg.norm(src[:, None, None, :] - x_samp[None], axis=-1).min(axis=2)
            ratio = dist / length[None, :]
            lo, hi = basis.element_bounds.T
            own = colloc.segment[rows][:, None] == k
            par = colloc.parameter[rows][:, None]
            singular = own & (par >= lo - 1e-12) & (par <= hi + 1e-12)
            is_far = (ratio >= s.far_ratio) & ~singular
            # far: dense block evaluation
            t_kernel, u_kernel = traction_and_displacement(
                src[:, None, None, :], x_far[None], n_far[None], shear_modulus=self.mu, nu=self.nu
            )
            weight = jw_far[None] * is_far[:, :, None]
            for kernel, target in ((t_kernel, h_mat), (u_kernel, g_mat)):
                block = np.einsum("ceqij,ceq,eqa->cijea", kernel, weight, phi_far, optimize=True)
                block = block.reshape(len(rows) * 4, n_el * n_loc) @ assembly
                block = block.reshape(len(rows), 2, 2, -1).transpose(0, 1, 3, 2)
                target[2 * rows[0] : 2 * rows[-1] + 2, col_slice] += block.reshape(
                    2 * len(rows), -1
                )
            # mid: one high-order rule per pair
            pr, pe = np.nonzero((ratio >= s.near_ratio) & ~is_far & ~singular)
            if pr.size:
                h, g = self._blocks(src[pr], *(array[pe] for array in mid_data))
                h_acc.add(rows[pr], cols_of[pe], h)
                g_acc.add(rows[pr], cols_of[pe], g)
            # near: graded composite rule toward the closest point
            pr, pe = np.nonzero((ratio < s.near_ratio) & ~singular)
            if pr.size:
                center, distance = _closest_local(basis, pe, src[pr])
                local, weights = _graded_rule(center, 2.0 * distance / length[pe], s)
                data = _pairs_quadrature(basis, pe, local, weights)
                h, g = self._blocks(src[pr], *data)
                h_acc.add(rows[pr], cols_of[pe], h)
                g_acc.add(rows[pr], cols_of[pe], g)
            pr, pe = np.nonzero(singular)
            if pr.size:
                singular_jobs.append((k, basis, rows[pr], pe))

    def _singular(self, k, basis, rows, elements, h_acc, g_acc):
        """Elements containing their collocation point: split there, log rule for G."""
        s = self.settings
        lo, hi = basis.element_bounds[elements].T
        center = np.clip(2.0 * (self.colloc.parameter[rows] - lo) / (hi - lo) - 1.0, -1.0, 1.0)
        at_source, _ = basis.shape_functions(elements, center)
        src = self.colloc.points[rows]
        cols = self.offsets[k] + basis.connectivity[elements]
        gauss = QuadratureRule.gauss_legendre(s.singular_points)
        u_gauss, w_gauss = 0.5 * (gauss.points + 1.0), 0.5 * gauss.weights  # on [0, 1]
        log_rule = QuadratureRule.gauss_log(s.log_points)
        for side in (-1.0, 1.0):
            length = np.where(side < 0, center + 1.0, 1.0 - center)  # local units
            live = length > 1e-12
            safe = np.where(live, length, 1.0)
            # Gauss points: H integrand bounded after subtraction; G smooth part
            t = safe[:, None] * u_gauss
            # a side of zero length (point at the element end) gets harmless points, weight 0
            local = np.where(live[:, None], center[:, None] + side * t, 0.0)
            points, normals, jw, values = _pairs_quadrature(
                basis, elements, local, safe[:, None] * w_gauss * live[:, None]
            )
            h, _ = self._blocks(src, points, normals, jw, values, subtract=at_source)
            h_acc.add(rows, cols, h)
            log_coef, smooth = displacement_parts(
                src[:, None, :], points, shear_modulus=self.mu, nu=self.nu
            )
            dist = np.linalg.norm(points - src[:, None, :], axis=-1)
            # -ln r = -ln t - ln(r / t); the -ln t part: log rule minus L ln L x Gauss
            log_factor = -np.log(dist / t) - np.log(safe)[:, None]
            kernel = smooth + (log_coef * log_factor)[..., None, None] * np.eye(2)
            g = np.einsum("pqij,pq,pqa->piaj", kernel, jw, values)
            log_local = np.where(
                live[:, None], center[:, None] + side * safe[:, None] * log_rule.points, 0.0
            )
            _, _, jw_log, values_log = _pairs_quadrature(
                basis, elements, log_local, safe[:, None] * log_rule.weights * live[:, None]
            )
            g += log_coef * np.einsum("pq,pqa,ij->piaj", jw_log, values_log, np.eye(2))
            g_acc.add(rows, cols, g)
