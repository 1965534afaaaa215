"""Collocation assembly of H and G for one body (paper eq. 8-10), vectorised.

Every (collocation point, element) pair falls in one of four classes, by the distance d
from the point to the element over the element's length h:

- far (d/h >= ``far_ratio``): a low-order Gauss rule, evaluated densely per block of rows;
- mid: a high-order Gauss rule;
- near (d/h < ``near_ratio``): a composite rule graded geometrically toward the element's
  closest point (adaptive subdivision);
- singular (the point lies on the element): the element is split at the point; G's
  ln(1/r) term by log-weighted Gauss (exact for log x polynomial), H by singularity
  subtraction with the rigid-body identity, which makes its integrand bounded.

The H rows come out already containing the free term c(x) u(x): with
H u = int T (u(x) - u(s)) dGamma, rigid translations give exactly zero (docs/theory.md).

Two implementations give the same H and G to round-off: this module's numpy code, and the
compiled loops of :mod:`fretbem._assembly_compiled` (numba), which classify and integrate
pair by pair without temporaries. Loading numba costs about 0.4 s in a fresh process, so
by default (``IntegrationSettings.compiled = None``) the compiled path is taken for bodies
with at least ``COMPILED_MIN_PAIRS`` (collocation point, element) pairs, where it repays
that, or once it is loaded anyway (docs/performance.md).
"""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Sequence

import attrs
import numpy as np
import scipy.sparse as sp

from .basis import Basis
from .kernels import KelvinKernel
from .quadrature import QuadratureRule


@attrs.frozen
class IntegrationSettings:
    """Quadrature orders and distance thresholds (see module docstring).

    ``compiled``: True for the compiled (numba) assembly, False for numpy, None to choose
    by problem size (``COMPILED_MIN_PAIRS``); the two give the same H and G to round-off.
    """

    far_ratio: float = 4.0
    far_points: int = 6
    near_ratio: float = 0.5
    mid_points: int = 16
    graded_points: int = 10
    graded_ratio: float = 0.5
    singular_points: int = 16
    log_points: int = 8
    block_rows: int = 256
    compiled: bool | None = attrs.field(
        default=None, validator=attrs.validators.optional(attrs.validators.instance_of(bool))
    )


#: (collocation point, element) pairs of one body from which the compiled path repays
#: loading numba in a fresh process (about 0.45 s for the import and the cached kernels,
#: against 1-2 us saved per pair; benchmarks/floor.py, docs/performance.md)
COMPILED_MIN_PAIRS = 400_000


class CompiledKernelsUnavailableError(RuntimeError):
    """``IntegrationSettings(compiled=True)`` was asked for but numba is not installed."""


def _numba_installed() -> bool:
    return importlib.util.find_spec("numba") is not None


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
    """Scatter-adds (rows, 2, n_local, 2) blocks into a dense 2N x 2M matrix in place."""

    def __init__(self, n_rows: int, n_cols: int):
        self.shape = (2 * n_rows, 2 * n_cols)
        self.flat = np.zeros(self.shape[0] * self.shape[1])

    def add(self, rows: np.ndarray, cols: np.ndarray, blocks: np.ndarray) -> None:
        """blocks[p, i, a, j] goes to (2 rows[p] + i, 2 cols[p, a] + j).

        ``np.add.at`` on the flat matrix: unbuffered (repeated indices add up), and no
        temporary of the matrix's size (a bincount with ``minlength`` would allocate one).
        """
        i = np.arange(2)
        r = 2 * rows[:, None, None, None] + i[None, :, None, None]
        c = 2 * cols[:, None, :, None] + i[None, None, None, :]
        np.add.at(self.flat, (r * self.shape[1] + c).ravel(), blocks.ravel())

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


def _distance_ratio(sources, samples, centres, radii, length, far_ratio):
    """min over an element's samples of the distance to each source, over its length.

    Exact where it decides the class; pairs whose bounding circle is already far by
    ``far_ratio`` get the circle's (lower-bound) ratio, which is only compared to it.
    """
    lower = np.linalg.norm(sources[:, None, :] - centres[None], axis=-1) - radii[None]
    ratio = lower * (1.0 - 1e-12) / length[None]
    pr, pe = np.nonzero(ratio < far_ratio)
    dist = np.linalg.norm(sources[pr, None, :] - samples[pe], axis=-1).min(axis=1)
    ratio[pr, pe] = dist / length[pe]
    return ratio


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
    """Builds H and G for a list of discretised segments of one homogeneous body.

    ``kernel`` is the fundamental solution integrated (plane strain or plane stress).
    """

    def __init__(
        self,
        segments: Sequence[Basis],
        kernel: KelvinKernel,
        settings: IntegrationSettings | None = None,
    ):
        if not isinstance(kernel, KelvinKernel):
            raise TypeError(
                f"Assembler needs a KelvinKernel (e.g. KelvinKernel.of(material)), got {kernel!r}"
            )
        self.segments = tuple(segments)
        self.kernel = kernel
        self.mu, self.nu = kernel.shear_modulus, kernel.effective_nu
        self.settings = settings or IntegrationSettings()
        self.offsets = offsets(self.segments)
        self.n = int(self.offsets[-1])
        self.colloc = Collocation.of(self.segments)

    # -- kernels times shape functions, contracted over quadrature points ------------------
    def _blocks(self, sources, points, normals, jw, values, *, subtract=None):
        """(P, 2, n_local, 2) blocks of H and G from per-pair quadrature data."""
        src = sources[:, None, :]
        t_kernel = self.kernel.traction(src, points, normals)
        u_kernel = self.kernel.displacement(src, points)
        phi_h = values if subtract is None else values - subtract[:, None, :]
        h = np.einsum("pqij,pq,pqa->piaj", t_kernel, jw, phi_h, optimize=True)
        g = np.einsum("pqij,pq,pqa->piaj", u_kernel, jw, values, optimize=True)
        return h, g

    @property
    def point_element_pairs(self) -> int:
        """Number of (collocation point, element) pairs: the assembly's work."""
        return self.n * sum(basis.n_elements for basis in self.segments)

    @property
    def uses_compiled(self) -> bool:
        """Whether :meth:`assemble` takes the compiled path (see the module docstring)."""
        choice = self.settings.compiled
        if choice is True and not _numba_installed():
            raise CompiledKernelsUnavailableError(
                "IntegrationSettings(compiled=True) needs numba, which is not installed; "
                "pip install numba, or leave compiled=None to use it only when available"
            )
        if choice is not None:
            return choice
        if "fretbem._compiled" in sys.modules:  # loaded already: its cost is paid
            return True
        return self.point_element_pairs >= COMPILED_MIN_PAIRS and _numba_installed()

    def assemble(self) -> tuple[np.ndarray, np.ndarray]:
        """Dense H and G, rows 2 s + i (collocation point s), columns 2 b + j (function b)."""
        if self.uses_compiled:
            from . import _assembly_compiled

            return _assembly_compiled.assemble(self, self.mu, self.nu)
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
        # a bounding circle of the samples: its distance is a lower bound of theirs
        centres = 0.5 * (x_samp.max(axis=1) + x_samp.min(axis=1))
        radii = np.linalg.norm(x_samp - centres[:, None], axis=-1).max(axis=1)
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
            ratio = _distance_ratio(src, x_samp, centres, radii, length, s.far_ratio)
            lo, hi = basis.element_bounds.T
            own = colloc.segment[rows][:, None] == k
            par = colloc.parameter[rows][:, None]
            singular = own & (par >= lo - 1e-12) & (par <= hi + 1e-12)
            is_far = (ratio >= s.far_ratio) & ~singular
            # far: dense block evaluation
            t_kernel, u_kernel = self.kernel.traction_and_displacement(
                src[:, None, None, :], x_far[None], n_far[None]
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
            log_coef, smooth = self.kernel.displacement_parts(src[:, None, :], points)
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
