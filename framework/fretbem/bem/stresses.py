"""Interior stresses of a BEM body by Somigliana's identity, as an evaluation matrix.

The stress at a point is linear in the boundary coefficients, so the operator is assembled
once per set of points, as a matrix mapping the stacked traction and displacement
coefficients of the body to (sigma_xx, sigma_yy, sigma_xy) at every point; each load step
is then one matrix product.

Quadrature, per (point, element) pair: a fixed Gauss rule when the point is farther from
the element than ``near_factor`` element lengths; otherwise a composite Gauss rule graded
geometrically toward the element's closest point. Points within ``subtract_factor`` local
element lengths of the boundary use singularity subtraction: the linear displacement field
whose stress is the boundary stress sigma0 at the closest boundary point x0 is reproduced
exactly by the identity, so

    sigma(x) = sigma0 + int D (t - sigma0 n) - int S (u - u0 - grad u0 (y - x0)),

whose integrands vanish at x0: the result tends to the boundary stress as x -> x0 and the
near-hypersingular cancellation (S ~ 1/r^2) disappears. Points on the boundary (closer
than ``boundary_tolerance`` element lengths) get the boundary stress itself. Theory:
docs/explanation/stress.rst.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.basis import Basis
from fretbem.errors import StressInputError
from fretbem.numerics.graded import graded_rule
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.validators import count_field, flag_field, number_field

from .boundary_state import boundary_state
from .stress_kernels import stress_kernels

#: Gauss points of the rule used where a point is farther than ``coarse_factor`` element
#: lengths from an element
COARSE_POINTS = 4

__all__ = ["StressOperator", "StressSettings", "somigliana_operator"]


def _lengths(default: float, *, low_open: bool = True) -> attrs.Converter:
    """A distance in element lengths, > 0 (or >= 0 where ``low_open`` is False)."""
    return number_field(
        "element lengths",
        f"give e.g. {default:g}",
        low=0.0,
        low_open=low_open,
        error=StressInputError,
    )


@attrs.frozen
class StressSettings:
    """Quadrature of the stress evaluation.

    Attributes
    ----------
    far_points : int
        Gauss points per element for far pairs.
    near_factor : float
        A pair is near when the point is closer than this many element lengths.
    graded_points, graded_ratio : int, float
        Gauss points per piece and the geometric ratio of the graded rule.
    subtract_factor : float
        Points closer to the boundary than this many (closest) element lengths use
        singularity subtraction.
    boundary_tolerance : float
        Points closer than this many element lengths are on the boundary (closer in, the
        subtracted integrals cancel to ~1e-16 h / d and round-off passes 1e-10).
    outside_tolerance : float
        Points outside the discretised boundary by less than this many element lengths
        (e.g. on the exact curve where an isoparametric boundary cuts a chord inside it) are
        taken as boundary points; farther outside is an error.
    chunk : int
        Points per block of the numpy far-field evaluation (memory).
    coarse_factor, far_factor : float
        The compiled loop uses a 4-point rule where a point is farther than
        ``coarse_factor`` element lengths from an element (beyond its bounding circle), and
        a 2-point rule beyond ``far_factor``.
    compiled : bool
        Use the numba far-field loop when numba is installed.
    """

    far_points: int = attrs.field(
        default=8, converter=count_field("give e.g. 8", low=2, error=StressInputError)
    )
    near_factor: float = attrs.field(default=0.7, converter=_lengths(0.7))
    graded_points: int = attrs.field(
        default=6, converter=count_field("give e.g. 6", low=2, error=StressInputError)
    )
    graded_ratio: float = attrs.field(
        default=0.35,
        converter=number_field(
            "a geometric ratio",
            "give e.g. 0.35",
            low=0.0,
            low_open=True,
            error=StressInputError,
        ),
    )
    subtract_factor: float = attrs.field(default=4.0, converter=_lengths(4.0, low_open=False))
    boundary_tolerance: float = attrs.field(default=1e-5, converter=_lengths(1e-5, low_open=False))
    outside_tolerance: float = attrs.field(default=1e-3, converter=_lengths(1e-3, low_open=False))
    chunk: int = attrs.field(
        default=256, converter=count_field("give e.g. 256", error=StressInputError)
    )
    coarse_factor: float = attrs.field(default=4.0, converter=_lengths(4.0))
    far_factor: float = attrs.field(default=30.0, converter=_lengths(30.0))
    compiled: bool = attrs.field(
        default=True, converter=flag_field("give True or False", error=StressInputError)
    )


@attrs.frozen(eq=False)
class StressOperator:
    """Matrix from boundary coefficients to stresses at fixed points.

    Attributes
    ----------
    points : ndarray (m, 2)
    matrix : ndarray (3 m, 4 N)
        Rows (point, component xx/yy/xy); columns the traction coefficients (N, 2) raveled,
        then the displacement coefficients (N, 2) raveled.
    nu, plane_stress : float, bool
        Poisson ratio (the material's) and plane stress flag, for sigma_zz.
    distance : ndarray (m,)
        Distance of each point to the boundary.
    closest : ndarray (m, 2)
        Closest boundary point.
    on_boundary : ndarray of bool (m,)
    """

    points: np.ndarray
    matrix: np.ndarray
    nu: float
    plane_stress: bool
    distance: np.ndarray
    closest: np.ndarray
    on_boundary: np.ndarray

    def apply(self, traction: np.ndarray, displacement: np.ndarray) -> np.ndarray:
        """Stresses (..., m, 4) [sxx, syy, sxy, szz] for coefficients (..., N, 2) each."""
        traction = np.asarray(traction, float)
        displacement = np.asarray(displacement, float)
        lead = traction.shape[:-2]
        data = np.concatenate(
            [traction.reshape(*lead, -1), displacement.reshape(*lead, -1)], axis=-1
        )
        if data.shape[-1] != self.matrix.shape[1]:
            raise StressInputError(
                f"the operator needs {self.matrix.shape[1] // 4} coefficients per field, got "
                f"{traction.shape[-2]}; build it from the same discretised body"
            )
        flat = np.einsum("rc,...c->...r", self.matrix, data)
        stress = flat.reshape(*lead, len(self.points), 3)
        szz = (
            np.zeros(stress.shape[:-1])
            if self.plane_stress
            else self.nu * (stress[..., 0] + stress[..., 1])
        )
        return np.concatenate([stress, szz[..., None]], axis=-1)

    def evaluate(self, solution) -> np.ndarray:
        """Stresses (m, 4) for a solved body's coefficients (``BodySolution``-like)."""
        return self.apply(solution.traction_coefficients, solution.displacement_coefficients)


@attrs.frozen(eq=False)
class _Elements:
    """Every element of the boundary, flattened over segments, with its far rule."""

    segment: np.ndarray  # (E,)
    local_index: np.ndarray  # (E,) element index inside its segment
    columns: np.ndarray  # (E, nl) global function index (padded with 0, weight 0)
    length: np.ndarray  # (E,)
    centre: np.ndarray  # (E, 2)
    radius: np.ndarray  # (E,)
    x: np.ndarray  # (E, q, 2)
    n: np.ndarray  # (E, q, 2)
    jw: np.ndarray  # (E, q)
    phi: np.ndarray  # (E, q, nl)
    samples: np.ndarray  # (E, 17, 2) points along each element, in boundary order
    coarse: tuple  # (x, n, jw, phi) of a 4-point rule, for elements far from a point
    farthest: tuple  # the same for a 2-point rule, for elements very far from a point

    @classmethod
    def of(cls, segments: Sequence[Basis], far_points: int) -> _Elements:
        fine = cls._rule(segments, QuadratureRule.gauss_legendre(far_points))
        coarse = cls._rule(segments, QuadratureRule.gauss_legendre(COARSE_POINTS))
        farthest = cls._rule(segments, QuadratureRule.gauss_legendre(2))
        return cls(*fine, coarse=coarse[6:10], farthest=farthest[6:10])

    @staticmethod
    def _rule(segments: Sequence[Basis], rule: QuadratureRule) -> list[np.ndarray]:
        samples = np.linspace(-1.0, 1.0, 17)
        n_local = max(b.n_local for b in segments)
        offset = 0
        parts = []
        for k, basis in enumerate(segments):
            n_el = basis.n_elements
            el = np.arange(n_el)
            m = basis.map(np.repeat(el, rule.points.size), np.tile(rule.points, n_el))
            q = rule.points.size
            jw = m.jacobians.reshape(n_el, q) * rule.weights
            phi = np.zeros((n_el, q, n_local))
            phi[:, :, : basis.n_local] = m.values.reshape(n_el, q, -1)
            cols = np.zeros((n_el, n_local), dtype=np.intp)
            cols[:, : basis.n_local] = offset + basis.connectivity
            pts = basis.geometry(np.repeat(el, samples.size), np.tile(samples, n_el))[0]
            pts = pts.reshape(n_el, samples.size, 2)
            centre = pts.mean(axis=1)
            radius = np.linalg.norm(pts - centre[:, None], axis=-1).max(axis=1)
            # chords between samples under-estimate a curved element slightly: pad
            radius = radius * 1.01 + 1e-14
            parts.append(
                (
                    np.full(n_el, k),
                    el,
                    cols,
                    jw.sum(axis=1),
                    centre,
                    radius,
                    m.points.reshape(n_el, q, 2),
                    m.normals.reshape(n_el, q, 2),
                    jw,
                    phi,
                    pts,
                )
            )
            offset += basis.n_functions
        return [np.concatenate(p) for p in zip(*parts, strict=True)]


#: the quadrature data of the latest segment tuples (by identity, the tuple kept so its id
#: is not reused): a run's stress grid, lines and fatigue points build several operators on
#: one body's segments (13 in examples/fretting_rig.toml), which the data do not depend on
_ELEMENTS: dict[tuple[int, int], tuple[Sequence[Basis], _Elements]] = {}
_ELEMENTS_KEPT = 8


def _elements_of(segments: Sequence[Basis], far_points: int) -> _Elements:
    """``_Elements.of(segments, far_points)``, made once per segment tuple (read only after);
    a list, which its caller may change in place, is not kept."""
    if not isinstance(segments, tuple):
        return _Elements.of(segments, far_points)
    key = (id(segments), far_points)
    kept = _ELEMENTS.get(key)
    if kept is not None and kept[0] is segments:
        return kept[1]
    elements = _Elements.of(segments, far_points)
    if len(_ELEMENTS) >= _ELEMENTS_KEPT:
        _ELEMENTS.pop(next(iter(_ELEMENTS)))
    _ELEMENTS[key] = (segments, elements)
    return elements


def _closest_local(basis: Basis, elements, points, iterations: int = 4):
    """Local coordinate on each element closest to each point (samples, then Newton)."""
    samples = np.linspace(-1.0, 1.0, 9)
    pts = basis.geometry(np.repeat(elements, samples.size), np.tile(samples, len(elements)))[0]
    dist = np.linalg.norm(pts.reshape(len(elements), samples.size, 2) - points[:, None], axis=-1)
    eta = samples[np.argmin(dist, axis=1)]
    for _ in range(iterations):
        x, tangent, *_ = basis.geometry(elements, eta)
        step = np.sum((x - points) * tangent, axis=-1) / np.sum(tangent**2, axis=-1)
        eta = np.clip(eta - step, -1.0, 1.0)
    x = basis.geometry(elements, eta)[0]
    return eta, np.linalg.norm(x - points, axis=-1)


def _closest_points(
    segments, elements: _Elements, points: np.ndarray, reach: np.ndarray, band: np.ndarray
):
    """Closest boundary points, computed exactly only where it matters.

    Pairs (point, element) whose bounding-circle distance is below ``reach`` (E,), and the
    two nearest elements of points within ``band`` (E,), get the exact closest local
    coordinate and distance. Returns those pairs, and per point the
    index of its best pair (-1 for points farther than every band: no near pair, no
    subtraction) and a lower bound of its distance to the boundary.
    """
    centre_dist = np.linalg.norm(points[:, None] - elements.centre[None], axis=-1)
    lower = centre_dist - elements.radius
    candidate = lower < reach[None]
    # in the subtraction band, the closest point is on one of the two nearest elements
    two = (
        np.argpartition(lower, 1, axis=1)[:, :2]
        if lower.shape[1] > 1
        else np.zeros((len(lower), 1), int)
    )
    rows = np.arange(len(points))[:, None]
    candidate[rows, two] |= lower[rows, two] < band[two]
    p_idx, e_idx = np.nonzero(candidate)
    eta = np.empty(len(p_idx))
    dist = np.empty(len(p_idx))
    for k, basis in enumerate(segments):
        sel = elements.segment[e_idx] == k
        if sel.any():
            eta[sel], dist[sel] = _closest_local(
                basis, elements.local_index[e_idx[sel]], points[p_idx[sel]]
            )
    best = np.full(len(points), np.inf)
    np.minimum.at(best, p_idx, dist)
    first = np.full(len(points), -1)
    order = np.flatnonzero(dist == best[p_idx])
    first[p_idx[order[::-1]]] = order[::-1]  # one best pair per point
    bound = np.maximum(lower.min(axis=1), 0.0)
    return first, p_idx, e_idx, eta, dist, bound


def _inside_polygon(elements: _Elements, points: np.ndarray) -> np.ndarray:
    """Points inside the boundary sampled as a polygon (for points away from it)."""
    from matplotlib.path import Path

    return Path(elements.samples.reshape(-1, 2)).contains_points(points)


def _weighted_kernels(x, y, n, w, nu: float, mu: float):
    """Weighted kernels D w, S w (..., 2, 3) at field points y (normals n) for points x."""
    r = y - x
    d, s = stress_kernels(r[..., 0], r[..., 1], n[..., 0], n[..., 1], nu, mu)
    return d * w[..., None, None], s * w[..., None, None]


def _identity_batch(p: int, n_local: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit traction and displacement coefficient sets, batch axis last (4 n_local)."""
    batch = np.zeros((p, n_local, 2, 4 * n_local))
    t, u = batch.copy(), batch.copy()
    for a in range(n_local):
        for k in range(2):
            t[:, a, k, 2 * a + k] = 1.0
            u[:, a, k, 2 * n_local + 2 * a + k] = 1.0
    return t, u


def _scatter_local(mt, mu_, rows, cols, coefficients):
    """Add per-point maps over local data (p, 3, 4 nl) to the global matrices."""
    n_local = cols.shape[1]
    for a in range(n_local):
        for k in range(2):
            np.add.at(mt, (rows, cols[:, a], k), coefficients[:, :, 2 * a + k])
            np.add.at(mu_, (rows, cols[:, a], k), -coefficients[:, :, 2 * (n_local + a) + k])


def _far_field_compiled():
    """The numba loop, or None where numba is not installed."""
    try:
        from .stress_compiled import far_field
    except ImportError:
        return None
    return far_field


def _far_field_numpy(points, elements, skip, sub_index, closest, nu, mu, mt, mu_, moments, chunk):
    """The far pairs in blocks of points (numpy): kernels, shape functions, one scatter."""
    mom_dn, mom_s, mom_sy = moments
    n_el, _, n_local = elements.phi.shape
    n_fun = mt.shape[1]
    scatter = np.zeros((n_el * n_local, n_fun))
    scatter[np.arange(n_el * n_local), elements.columns.ravel()] = 1.0
    for start in range(0, len(points), chunk):
        rows = np.arange(start, min(start + chunk, len(points)))
        rows = rows[~skip[rows].all(axis=1)]
        if not rows.size:
            continue
        w = elements.jw[None] * ~skip[rows][:, :, None]
        d, s = _weighted_kernels(
            points[rows, None, None], elements.x[None], elements.n[None], w, nu, mu
        )
        for target, kern in ((mt, d), (mu_, s)):
            local = np.einsum("peqkc,eqa->peakc", kern, elements.phi)
            target[rows] += np.matmul(
                scatter.T, local.reshape(len(rows), n_el * n_local, 6)
            ).reshape(len(rows), n_fun, 2, 3)
        sub = sub_index[rows] >= 0
        if sub.any():
            si = sub_index[rows[sub]]
            mom_dn[si] += np.einsum("peqkc,eql->pkcl", d[sub], elements.n)
            mom_s[si] += np.einsum("peqkc->pkc", s[sub])
            mom_sy[si] += np.einsum(
                "peqkc,peql->pkcl", s[sub], elements.x[None] - closest[rows[sub], None, None]
            )


def somigliana_operator(
    segments: Sequence[Basis],
    points: np.ndarray,
    *,
    shear_modulus: float,
    nu: float,
    plane_stress: bool = False,
    settings: StressSettings | None = None,
) -> StressOperator:
    """The stress evaluation matrix of a body discretised by ``segments`` at ``points``.

    ``nu`` is the material's Poisson ratio; plane stress uses nu / (1 + nu) in the kernels.
    Raises StressInputError for points outside the body.
    """
    settings = settings or StressSettings()
    points = np.atleast_2d(np.asarray(points, float))
    if points.ndim != 2 or points.shape[1] != 2 or not np.all(np.isfinite(points)):
        raise StressInputError(f"points must be a finite (m, 2) array, got shape {points.shape}")
    knu = nu / (1.0 + nu) if plane_stress else float(nu)
    mu = float(shear_modulus)
    elements = _elements_of(segments, settings.far_points)
    offsets = np.concatenate([[0], np.cumsum([b.n_functions for b in segments])])
    n_fun = int(offsets[-1])
    m, n_el = len(points), len(elements.length)

    reach = settings.near_factor * elements.length
    band = max(settings.near_factor, settings.subtract_factor) * elements.length
    first, p_idx, e_idx, eta, dist, bound = _closest_points(segments, elements, points, reach, band)
    banded = first >= 0
    distance = bound.copy()
    distance[banded] = dist[first[banded]]
    near = dist < reach[e_idx]
    near_mask = np.zeros((m, n_el), dtype=bool)
    near_mask[p_idx[near], e_idx[near]] = True

    best_e, best_eta = e_idx[first[banded]], eta[first[banded]]
    closest = np.full((m, 2), np.nan)
    normal = np.full((m, 2), np.nan)
    rows_b = np.flatnonzero(banded)
    for k, basis in enumerate(segments):
        sel = elements.segment[best_e] == k
        if sel.any():
            mp = basis.map(elements.local_index[best_e[sel]], best_eta[sel])
            closest[rows_b[sel]], normal[rows_b[sel]] = mp.points, mp.normals
    scale = np.full(m, np.inf)
    scale[banded] = elements.length[best_e]
    outside = np.zeros(m, dtype=bool)
    outside[banded] = np.sum((points - closest)[banded] * normal[banded], axis=1) > 0
    if (~banded).any():
        outside[~banded] = ~_inside_polygon(elements, points[~banded])
    on_boundary = banded & (distance <= settings.boundary_tolerance * scale)
    on_boundary |= banded & outside & (distance <= settings.outside_tolerance * scale)
    outside &= ~on_boundary
    if outside.any():
        i = int(np.flatnonzero(outside)[0])
        raise StressInputError(
            f"{int(outside.sum())} of {m} points lie outside the body (first: "
            f"{points[i].tolist()}, at least {distance[i]:.3g} from the boundary); evaluate "
            "them in the other body or move them inside"
        )
    subtract = banded & ~on_boundary
    subtract[banded] &= distance[banded] < settings.subtract_factor * scale[banded]
    integrate = ~on_boundary
    near_mask[on_boundary] = True  # nothing is integrated for boundary points

    # the matrix in its final layout [point, component, (traction, displacement), function,
    # direction]; mt and mu_ are views [point, function, direction, component] of its halves
    full = np.zeros((m, 3, 2, n_fun, 2))
    mt = full[:, :, 0].transpose(0, 2, 3, 1)
    mu_ = full[:, :, 1].transpose(0, 2, 3, 1)
    sub_index = np.full(m, -1)
    n_sub = int(subtract.sum())
    sub_index[subtract] = np.arange(n_sub)
    mom_dn = np.zeros((n_sub, 2, 3, 2))  # int D_kc n_l
    mom_s = np.zeros((n_sub, 2, 3))  # int S_kc
    mom_sy = np.zeros((n_sub, 2, 3, 2))  # int S_kc (y - x0)_l

    # far pairs: the same rule on every element
    skip = near_mask | ~integrate[:, None]
    # boundary points only (a surface scan) have no far pair: numba is not even loaded
    if not skip.all():
        far = _far_field_compiled() if settings.compiled else None
        if far is not None:
            far(
                points, elements.x, elements.n, elements.jw, elements.phi, *elements.coarse,
                *elements.farthest, elements.centre,
                elements.radius + settings.coarse_factor * elements.length,
                elements.radius + settings.far_factor * elements.length,
                elements.columns, skip, sub_index, closest, knu, mu, full, mom_dn, mom_s, mom_sy,
            )  # fmt: skip
        else:
            _far_field_numpy(
                points, elements, skip, sub_index, closest, knu, mu, mt, mu_,
                (mom_dn, mom_s, mom_sy), settings.chunk,
            )  # fmt: skip

    # near pairs: graded composite rule toward the closest point of the element
    keep = near & integrate[p_idx]
    near_p, near_e, near_eta, near_d = p_idx[keep], e_idx[keep], eta[keep], dist[keep]
    for k, basis in enumerate(segments):
        sel = elements.segment[near_e] == k
        if not sel.any():
            continue
        rows, el, centre = near_p[sel], elements.local_index[near_e[sel]], near_eta[sel]
        jac = basis.map(el, centre).jacobians
        local, weight = graded_rule(
            centre, near_d[sel] / jac, settings.graded_points, settings.graded_ratio
        )
        q = local.shape[1]
        mp = basis.map(np.repeat(el, q), local.ravel())
        y = mp.points.reshape(-1, q, 2)
        nq = mp.normals.reshape(-1, q, 2)
        w = mp.jacobians.reshape(-1, q) * weight
        values = mp.values.reshape(-1, q, basis.n_local)
        d, s = _weighted_kernels(points[rows, None], y, nq, w, knu, mu)
        cols = offsets[k] + basis.connectivity[el]
        np.add.at(mt, (rows[:, None], cols), np.einsum("pqkc,pqa->pakc", d, values))
        np.add.at(mu_, (rows[:, None], cols), np.einsum("pqkc,pqa->pakc", s, values))
        sub = subtract[rows]
        if sub.any():
            si = sub_index[rows[sub]]
            np.add.at(mom_dn, si, np.einsum("pqkc,pql->pkcl", d[sub], nq[sub]))
            np.add.at(mom_s, si, np.einsum("pqkc->pkc", s[sub]))
            np.add.at(
                mom_sy, si, np.einsum("pqkc,pql->pkcl", s[sub], y[sub] - closest[rows[sub], None])
            )

    # subtraction and boundary points: the boundary state at the closest point
    special = subtract | on_boundary
    comp = ((0, 0), (1, 1), (0, 1))
    point_e = np.full(m, -1)
    point_e[banded] = best_e
    point_eta = np.zeros(m)
    point_eta[banded] = best_eta
    for k, basis in enumerate(segments):
        sel = special & (elements.segment[point_e] == k)
        if not sel.any():
            continue
        rows = np.flatnonzero(sel)
        el, centre = elements.local_index[point_e[rows]], point_eta[rows]
        values, derivatives = basis.shape_functions(el, centre)
        tangents = basis.geometry(el, centre)[1]
        t_batch, u_batch = _identity_batch(len(rows), basis.n_local)
        stress0, u0, grad = boundary_state(
            values, derivatives, tangents, t_batch, u_batch, shear_modulus=mu, nu=knu
        )
        s0 = np.stack([stress0[:, i, j] for i, j in comp], axis=1)  # (p, 3, B)
        coefficients = s0.copy()
        is_sub = subtract[rows]
        if is_sub.any():
            si = sub_index[rows[is_sub]]
            coefficients[is_sub] += (
                -np.einsum("pkcl,pklb->pcb", mom_dn[si], stress0[is_sub])
                + np.einsum("pkc,pkb->pcb", mom_s[si], u0[is_sub])
                + np.einsum("pkcl,pklb->pcb", mom_sy[si], grad[is_sub])
            )
        cols = offsets[k] + basis.connectivity[el]
        _scatter_local(mt, mu_, rows, cols, coefficients)

    full[:, :, 1] *= -1.0  # sigma = int D t - int S u
    matrix = full.reshape(3 * m, 4 * n_fun)
    return StressOperator(
        points=points,
        matrix=matrix,
        nu=float(nu),
        plane_stress=bool(plane_stress),
        distance=distance,
        closest=closest,
        on_boundary=on_boundary,
    )
