"""Surface influence coefficients of an elastic half-plane (Flamant / Boussinesq line loads).

A line force (F_x, F_y) on the surface of a half-plane at x = s displaces the surface point
x by (Johnson, Contact Mechanics, 1985, eqs. 2.19-2.20)

    u_x = -A ln(|x - s| / d0) F_x + sigma B sign(x - s) F_y
    u_y = -sigma B sign(x - s) F_x - A ln(|x - s| / d0) F_y

with A = (kappa + 1) / (4 pi mu), B = (kappa - 1) / (8 mu) (kappa = 3 - 4 nu in plane strain,
(3 - nu) / (1 + nu) in plane stress), sigma = +1 for a body below its surface and -1 for a
body above it, and d0 the datum distance at which the ln r displacement is zero. Integrating
these against the shape functions of a discretised face gives the displacement at any surface
point per unit traction coefficient; through the face's E matrix, per unit node traction.
"""

from __future__ import annotations

import functools
import math

import attrs
import numpy as np

from fretbem.basis import Basis, ElementMap
from fretbem.errors import InputError
from fretbem.material import Material
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.validators import positive

SIDES = ("lower", "upper")

#: default datum distance d0 (mm): a typical specimen thickness. Only a rigid translation of
#: each body depends on it; a d0 much larger than the contact face also keeps the constant
#: (rank-one) part of the compliance from swamping its diagonal, which the Newton solver's
#: augmentation parameters are scaled by (d0 = 0.1 mm made it cycle at 61 pairs)
DEFAULT_DATUM = 10.0

#: Gauss-Legendre points per element of the face's own integrals (the face check, force and
#: moment weights) and of the influence integrals of elements within FAR_RATIO but at least
#: CLOSE_RATIO of their lengths from a field point: ln's singularity then lies outside the
#: Bernstein ellipse rho = 1.9 + sqrt(1.9^2 - 1) = 3.52, so the rule's relative error is
#: about rho^(-2 SMOOTH_POINTS) = 8e-14. CLOSE_RATIO is under one half so that on a uniform
#: face, whose nodes sit mid-element in the parameter (half an element from the neighbours'
#: ends in x to within the curvature's 2e-6), the neighbours take this rule, not the graded
#: pieces
SMOOTH_POINTS = 12
CLOSE_RATIO = 0.45
#: Gauss-Legendre points per (sub)interval of the influence integrals nearer than that, and
#: Gauss-log points per singular piece: each integrand there is smooth (the shape functions
#: times ln of a distance at least the piece's length away, or times ln(r / t), analytic),
#: so 8 and 6 points reach round-off. With these rules the integrals lie within 3.7e-14 of
#: their largest entry from a 30-point converged quadrature (nurbs degree 2-4 and lagrange2
#: faces of 21-481 pairs, at the nodes and at random surface points; 4e-14 with 12 points
#: everywhere and no CLOSE_RATIO rule)
NEAR_POINTS = 8
LOG_POINTS = 6
#: elements at least FAR_RATIO of their lengths from a field point take FAR_POINTS
#: Gauss-Legendre points: ln's singularity then lies beyond the Bernstein ellipse
#: rho = 2 FAR_RATIO + 1 + sqrt((2 FAR_RATIO + 1)^2 - 1) = 15.9, so the rule's relative error
#: is about rho^(-2 FAR_POINTS) = 1e-14 (measured on the reference scene: node maps within
#: 1e-14 of the twelve-point rule's)
FAR_RATIO = 4.0
FAR_POINTS = 6
#: Newton iterations (kept in a bisection bracket) locating a field point inside an element
INVERT_ITERATIONS = 60


class HalfPlaneFaceError(InputError):
    """A contact face that cannot be the surface of a half-plane."""


@attrs.frozen
class FlamantCompliance:
    """The two constants of the surface line-load solution of a half-plane.

    Attributes
    ----------
    log : float
        A = (kappa + 1) / (4 pi mu): 2 (1 - nu^2) / (pi E) in plane strain, 2 / (pi E) in
        plane stress; multiplies -ln(|x - s| / d0).
    jump : float
        B = (kappa - 1) / (8 mu): (1 - 2 nu)(1 + nu) / (2 E) in plane strain, (1 - nu) / (2 E)
        in plane stress; half the jump of the coupled displacement across the load.
    """

    log: float = attrs.field(converter=float, validator=positive)
    jump: float = attrs.field(converter=float)

    @classmethod
    def of(cls, material: Material) -> FlamantCompliance:
        """Constants for a material, plane strain or plane stress as the material says."""
        nu, mu = material.nu, material.shear_modulus
        kappa = (3.0 - nu) / (1.0 + nu) if material.plane_stress else 3.0 - 4.0 * nu
        return cls(log=(kappa + 1.0) / (4.0 * math.pi * mu), jump=(kappa - 1.0) / (8.0 * mu))

    def bulk_strain(self, material: Material) -> float:
        """Surface strain du_x/dx per unit far-field stress sigma_xx (Hooke's law)."""
        if material.plane_stress:
            return 1.0 / material.E
        return (1.0 - material.nu**2) / material.E


def side_sign(side: str) -> float:
    """sigma of the line-load formulas: +1 for a body below its surface, -1 above."""
    if side not in SIDES:
        raise HalfPlaneFaceError(
            f"a half-plane lies 'lower' (below its surface) or 'upper' (above it), got {side!r}"
        )
    return 1.0 if side == "lower" else -1.0


def line_load_displacement(
    material: Material, side: str, x, s: float, datum: float = 1.0
) -> np.ndarray:
    """Surface displacement (m, 2, 2) at points ``x`` per unit line force at ``s``.

    Entry [k, i, j] is displacement component i at x[k] per unit force component j: the
    closed form the influence coefficients integrate (and the tests check them against).
    """
    x = np.asarray(x, dtype=float)
    c = FlamantCompliance.of(material)
    sigma = side_sign(side)
    log = -c.log * np.log(np.abs(x - s) / datum)
    jump = sigma * c.jump * np.sign(x - s)
    out = np.empty((*x.shape, 2, 2))
    out[..., 0, 0] = out[..., 1, 1] = log
    out[..., 0, 1] = jump
    out[..., 1, 0] = -jump
    return out


@attrs.frozen(eq=False)
class SurfaceIntegrals:
    """Integrals of each shape function against ln(|x - s| / d0) and sign(x - s).

    Attributes
    ----------
    log, sign : ndarray, shape (m, n_functions)
        Row k: the integrals for field point x[k]; column b: the face's function b.
    """

    log: np.ndarray
    sign: np.ndarray


def _element_map(face: Basis, elements: np.ndarray, local: np.ndarray):
    """Projected position x(xi) and |dx/dxi| with the shape-function values.

    On one segment, :meth:`Basis.abscissae` (x and dx/dxi summed as :meth:`Basis.map` sums
    them, the same numbers, without the y, Jacobian and normal it also forms, which the
    integrals never read); a joined face maps through its parts."""
    if not isinstance(face, Basis):
        m = face.map(elements, local)
        return m.points[:, 0], np.abs(m.tangents[:, 0]), m.values
    x, dx, values = face.abscissae(elements, local)
    return x, np.abs(dx, out=dx), values


def gauss_samples(face: Basis, mapped: ElementMap | None = None):
    """The face mapped at the SMOOTH_POINTS-point Gauss-Legendre rule of every element:
    (element of each point, its rule weight, the mapping); the face check and the force
    and moment integrals all read these points. ``mapped``: the face's :func:`rule_map`,
    whose first rows are these (the same numbers: each point is mapped alone)."""
    elements, weights = _sample_table(face.n_elements)
    if mapped is None:
        rule = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
        return elements, weights, face.map(elements, np.tile(rule.points, face.n_elements))
    return elements, weights, _map_rows(mapped, slice(elements.size))


@functools.lru_cache(maxsize=32)
def _sample_table(n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """The element and rule weight of every smooth-rule point of :func:`gauss_samples`
    (tabulated per element count, read-only)."""
    rule = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    elements = np.repeat(np.arange(n_elements), rule.points.size)
    weights = np.tile(rule.weights, n_elements)
    for array in (elements, weights):
        array.setflags(write=False)
    return elements, weights


@functools.lru_cache(maxsize=32)
def _rule_points(n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """(elements, local coordinates) :func:`surface_integrals` maps: every element's
    smooth-rule points (the Gauss samples' rows), then its ends and coarse-rule points
    (tabulated per element count, like the rules themselves: read-only)."""
    smooth = QuadratureRule.gauss_legendre(SMOOTH_POINTS).points
    rest = np.concatenate([[-1.0, 1.0], QuadratureRule.gauss_legendre(FAR_POINTS).points])
    numbers = np.arange(n_elements)
    elements = np.concatenate([np.repeat(numbers, smooth.size), np.repeat(numbers, rest.size)])
    local = np.concatenate([np.tile(smooth, n_elements), np.tile(rest, n_elements)])
    for array in (elements, local):
        array.setflags(write=False)
    return elements, local


def rule_map(face) -> ElementMap:
    """The face mapped at every element's smooth-rule points, then at its ends and
    coarse-rule points: the one basis evaluation of :func:`surface_integrals` (its
    ``mapped``) and, in its first rows, of :func:`gauss_samples`, for a surface that needs
    both."""
    return face.map(*_rule_points(face.n_elements))


def rule_map_with(face, elements: np.ndarray, local: np.ndarray) -> tuple[ElementMap, ElementMap]:
    """:func:`rule_map` and the face's map at (``elements``, ``local``), from one basis
    evaluation: the same numbers as two (each point is mapped alone), one call's overhead."""
    rule_elements, rule_local = _rule_points(face.n_elements)
    both = face.map(np.concatenate([rule_elements, elements]),
                    np.concatenate([rule_local, local]))  # fmt: skip
    return _map_rows(both, slice(rule_elements.size)), _map_rows(
        both, slice(rule_elements.size, None)
    )


def _map_rows(mapped: ElementMap, rows: slice) -> ElementMap:
    """The rows ``rows`` of an element map (views)."""
    return ElementMap(
        mapped.values[rows], mapped.points[rows], mapped.tangents[rows],
        mapped.jacobians[rows], mapped.normals[rows],
    )  # fmt: skip


def check_face(face: Basis, samples=None) -> None:
    """Require x to run monotonically along the face: it is the graph of a surface profile.

    ``samples``: the face's :func:`gauss_samples`, if already computed."""
    dx = (gauss_samples(face) if samples is None else samples)[2].tangents[:, 0]
    if not (np.all(dx > 0) or np.all(dx < 0)):
        raise HalfPlaneFaceError(
            "a half-plane face must run monotonically in x (it is the graph y(x) of the "
            "surface profile over the half-plane's straight surface), but x turns back along "
            "this face; describe the face as a curve whose x always increases or decreases"
        )


def _invert(face: Basis, elements: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Local coordinate where x(xi) = target on each element.

    Newton from the chord's guess, kept inside a bisection bracket (x is monotone): about
    five basis evaluations where plain bisection to round-off took sixty-two.
    """
    m = len(elements)
    ends = _element_map(face, np.concatenate([elements, elements]), np.repeat([-1.0, 1.0], m))[0]
    x_lo, x_hi = ends[:m], ends[m:]
    increasing = x_hi > x_lo
    lo, hi = np.full(m, -1.0), np.full(m, 1.0)
    span = np.where(x_hi == x_lo, 1.0, x_hi - x_lo)
    xi = np.clip(-1.0 + 2.0 * (targets - x_lo) / span, -1.0, 1.0)
    # x(xi) is known to a few ulp of x: a point is found once its miss is that small
    resolution = 8.0 * np.finfo(float).eps * (np.abs(x_lo) + np.abs(x_hi))
    for _ in range(INVERT_ITERATIONS):
        mapped = face.map(elements, xi)
        miss = mapped.points[:, 0] - targets
        found = np.abs(miss) <= resolution
        if found.all():
            break
        move_hi = (miss > 0) == increasing
        hi = np.where(move_hi, xi, hi)
        lo = np.where(move_hi, lo, xi)
        with np.errstate(divide="ignore", invalid="ignore"):
            new = xi - miss / mapped.tangents[:, 0]
        outside = ~((new >= lo) & (new <= hi))  # also catches nan
        new = np.where(outside, 0.5 * (lo + hi), new)
        xi = np.where(found, xi, new)
    return xi


def surface_integrals(
    face: Basis, x, datum: float = 1.0, at=None, mapped: ElementMap | None = None
) -> SurfaceIntegrals:
    """ln and sign integrals of the face's shape functions for field points ``x`` on the surface.

    ``at``: (element, local coordinate) of each point of ``x`` on the face where it is one
    of the face's own points (its nodes: ``face.collocation()``), whose split in its own
    element then needs no search for the local coordinate. ``mapped``: the face's
    :func:`rule_map`, if already computed (the same numbers as mapping here: x and its
    derivative are summed as ``Basis.map`` sums them).

    Elements at least FAR_RATIO lengths away use a FAR_POINTS Gauss-Legendre rule, nearer
    ones but at least CLOSE_RATIO of their length away a SMOOTH_POINTS rule (both
    vectorised over every field point; the ln kernel's nearest singularity bounds either
    rule's error near 1e-14 of the element's integral); a nearer element is split at the
    field point, with a Gauss-log rule for ln t on each piece, or graded geometrically
    toward the field point when it lies just outside. On a uniform face with its nodes in
    the middle of their elements every neighbour lies half an element away or more: only
    each node's own element is split, none is graded.
    """
    x = np.asarray(x, dtype=float).ravel()
    smooth = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    coarse = QuadratureRule.gauss_legendre(FAR_POINTS)
    n_el, n_c = face.n_elements, coarse.points.size
    # one basis evaluation for the smooth rule, both element ends and the coarse rule
    if mapped is None:
        xq, jac, values = _element_map(face, *_rule_points(n_el))
    else:
        xq, jac, values = mapped.points[:, 0], np.abs(mapped.tangents[:, 0]), mapped.values
    n_s = n_el * smooth.points.size
    xq_s, jac_s = xq[:n_s].reshape(n_el, -1), jac[:n_s].reshape(n_el, -1)
    rest, jac_rest = xq[n_s:].reshape(n_el, -1), jac[n_s:].reshape(n_el, -1)
    values_s = values[:n_s].reshape(n_el, smooth.points.size, -1)
    values_c = values[n_s:].reshape(n_el, 2 + n_c, -1)[:, 2:]
    ends, xq_c = rest[:, :2], rest[:, 2:]
    weighted_c = (jac_rest[:, 2:] * coarse.weights)[..., None] * values_c
    weights_s = jac_s * smooth.weights
    weighted_s = weights_s[..., None] * values_s
    # the smaller and larger end of each element (a reduction over two: the same numbers)
    left, right = np.minimum(ends[:, 0], ends[:, 1]), np.maximum(ends[:, 0], ends[:, 1])
    length = right - left
    distance = np.maximum(np.maximum(left[None, :] - x[:, None], x[:, None] - right[None, :]), 0)
    # every pair by the coarse rule first: (elements, points, rule) @ (elements, rule, local)
    kernel = _log_kernel(x[None, :, None], xq_c[:, None, :], datum)
    log_el = np.matmul(kernel, weighted_c).transpose(1, 0, 2)  # (points, elements, local)
    del kernel
    close = CLOSE_RATIO * length[None, :]
    mid_k, mid_e = np.nonzero((distance < FAR_RATIO * length[None, :]) & (distance >= close))
    if mid_k.size:
        kernel = _log_kernel(x[mid_k, None], xq_s[mid_e], datum)
        log_el[mid_k, mid_e] = np.einsum("pg,pga->pa", kernel, weighted_s[mid_e])
    moments = weighted_s.sum(axis=1)
    centre = 0.5 * (left + right)
    sign = _far_sign(face, x, centre, moments)
    near_k, near_e = np.nonzero(distance < close)
    if near_k.size:
        known = None
        if at is not None:  # the local coordinate of a point in its own element
            own = np.asarray(at[0])[near_k] == near_e
            known = np.where(own, np.asarray(at[1], float)[near_k], np.nan)
        log_el[near_k, near_e], near_sign = _near(
            face, near_e, x[near_k], datum, ends[near_e], known
        )
        # the near pairs' sign integrals replace the whole-element terms counted for them
        before = centre[near_e] < x[near_k]  # the element was counted whole before x
        counted = np.where(before, 1.0, -1.0)[:, None] * moments[near_e]
        np.add.at(sign, (near_k[:, None], face.connectivity[near_e]), near_sign - counted)
    return SurfaceIntegrals(_to_functions(face, log_el), sign)


def _far_sign(face: Basis, x: np.ndarray, centre: np.ndarray, moments: np.ndarray):
    """The sign integrals (points, functions) with every element taken whole, sign(x - s) =
    +1 on an element whose centre lies before x and -1 on the others.

    Summed as twice the running sum of the elements' moments in the order of their centres,
    taken where x falls, minus the total: O(points x functions) work, where forming every
    (point, element, function) term first cost ~10x more at 481 nodes.
    """
    order = np.argsort(centre, kind="stable")
    running = np.zeros((centre.size + 1, face.n_functions))
    rows = np.arange(1, centre.size + 1)[:, None]
    running[rows, face.connectivity[order]] = moments[order]
    np.cumsum(running, axis=0, out=running)
    position = np.searchsorted(centre[order], x, side="left")  # elements before x
    sign = running[position]
    sign *= 2.0
    sign -= running[-1]
    return sign


def _log_kernel(x: np.ndarray, xq: np.ndarray, datum: float) -> np.ndarray:
    """ln(|x - xq| / datum) (broadcast), computed in place in one array: the numbers of
    ``np.log(np.abs(x - xq) / datum)`` without its three temporaries."""
    out = np.subtract(x, xq)
    np.abs(out, out=out)
    np.divide(out, datum, out=out)
    return np.log(out, out=out)


def _to_functions(face: Basis, per_element: np.ndarray) -> np.ndarray:
    """(points, functions) sums of per-element integrals (points, elements, local)."""
    out = np.zeros((per_element.shape[0], face.n_functions))
    connectivity = face.connectivity
    n_el = connectivity.shape[0]
    # which local functions run over consecutive columns element after element (a spline
    # face's all): their sums are slices, found in one pass over the connectivity
    steps = np.diff(connectivity, axis=0)
    consecutive = (steps == 1).all(axis=0) if n_el > 1 else np.zeros(connectivity.shape[1], bool)
    for a in range(connectivity.shape[1]):
        columns = connectivity[:, a]
        if consecutive[a]:
            first = columns[0]
            out[:, first : first + n_el] += per_element[:, :, a]  # a slice: no gather
        elif np.unique(columns).size == columns.size:  # one element per function: no clash
            out[:, columns] += per_element[:, :, a]
        else:
            for e, column in enumerate(columns):
                out[:, column] += per_element[:, e, a]
    return out


def _near(face: Basis, e: np.ndarray, xk: np.ndarray, datum: float, ends: np.ndarray,
          known=None):  # fmt: skip
    """Integrals over elements ``e`` for field points ``xk`` on or just beside them.

    ``ends`` (m, 2) holds x at local -1 and +1 of each element; ``known`` (m,), if given,
    each point's local coordinate in its element where known (nan elsewhere).
    """
    length = np.abs(ends[:, 1] - ends[:, 0])
    tol = 1e-12 * length
    low, high = np.minimum(ends[:, 0], ends[:, 1]), np.maximum(ends[:, 0], ends[:, 1])
    inside = (xk >= low - tol) & (xk <= high + tol)
    if inside.all():  # every point in its element (a face's own nodes): split them all
        return _split(face, e, xk, datum, ends, known)
    log_out = np.zeros((len(e), face.n_local))
    sign_out = np.zeros((len(e), face.n_local))
    if inside.any():
        log_out[inside], sign_out[inside] = _split(
            face, e[inside], xk[inside], datum, ends[inside],
            None if known is None else known[inside],
        )  # fmt: skip
    outside = ~inside
    if outside.any():
        log_out[outside], sign_out[outside] = _graded(
            face, e[outside], xk[outside], datum, ends[outside]
        )
    return log_out, sign_out


def _split(face: Basis, e, xk, datum, ends, known=None):
    """Elements containing their field point: split there, ln t by the Gauss-log rule
    (``known``: the points' local coordinates where known, nan where to be found)."""
    tol = 1e-12 * np.abs(ends[:, 1] - ends[:, 0])
    if known is None:
        star = _invert(face, e, xk)
    else:
        star = np.array(known, dtype=float)
        unknown = np.isnan(star)
        if unknown.any():
            star[unknown] = _invert(face, e[unknown], xk[unknown])
    star = np.where(np.abs(xk - ends[:, 0]) <= tol, -1.0, star)
    star = np.where(np.abs(xk - ends[:, 1]) <= tol, 1.0, star)
    t_smooth, w_smooth, log_weights, t = _split_rules()
    n_s = t_smooth.size
    # both pieces xi = star + h t (h = end - star, t in [0, 1]), both rules, one evaluation
    h = np.empty((star.size, 2))  # (m, 2): np.stack's numbers without its checks
    np.subtract(-1.0, star, out=h[:, 0])
    np.subtract(1.0, star, out=h[:, 1])
    empty = np.abs(h) < 1e-14
    h = np.where(empty, 0.0, h)
    xs, jac, values = _map_at(face, e, (star[:, None, None] + h[..., None] * t).reshape(len(e), -1))
    xs, jac = xs.reshape(len(e), 2, -1), jac.reshape(len(e), 2, -1)
    values = values.reshape(len(e), 2, t.size, -1)
    scale = jac * np.abs(h)[..., None]
    # ln|x - xk| = ln t + ln(|x - xk| / t) on the smooth rule; -ln t by the Gauss-log rule
    r_over_t = np.where(empty[..., None], 1.0, np.abs(xs[..., :n_s] - xk[:, None, None])) / t_smooth
    f = (scale[..., :n_s] * w_smooth)[..., None] * values[..., :n_s, :]
    log_sum = np.einsum("mhg,mhga->ma", np.log(r_over_t / datum), f)
    sign_sum = np.einsum("mhg,mhga->ma", np.sign(xk[:, None, None] - xs[..., :n_s]), f)
    log_f = (scale[..., n_s:] * log_weights)[..., None] * values[..., n_s:, :]
    log_sum -= log_f.sum(axis=(1, 2))
    return log_sum, sign_sum


@functools.cache
def _split_rules() -> tuple[np.ndarray, ...]:
    """:func:`_split`'s rules on t in [0, 1]: the NEAR_POINTS Gauss-Legendre points and
    weights, the LOG_POINTS Gauss-log weights, and both rules' points in one row."""
    smooth = QuadratureRule.gauss_legendre(NEAR_POINTS)
    log_rule = QuadratureRule.gauss_log(LOG_POINTS)
    t_smooth, w_smooth = 0.5 * (smooth.points + 1.0), 0.5 * smooth.weights
    rules = (t_smooth, w_smooth, log_rule.weights, np.concatenate([t_smooth, log_rule.points]))
    for array in rules:
        array.setflags(write=False)
    return rules


def _graded(face: Basis, e, xk, datum, ends):
    """Field points just outside: pieces growing geometrically from the near end, each as
    long as its distance to the field point, so one Gauss-Legendre rule resolves ln on each."""
    smooth = QuadratureRule.gauss_legendre(NEAR_POINTS)
    t_smooth, w_smooth = 0.5 * (smooth.points + 1.0), 0.5 * smooth.weights
    to_end = np.abs(xk[:, None] - ends)
    near_end = np.where(to_end[:, 0] < to_end[:, 1], -1.0, 1.0)
    step = 2.0 * to_end.min(axis=1) / np.abs(ends[:, 1] - ends[:, 0])  # gap in local units
    levels = int(np.ceil(np.log2(2.0 / step.min() + 1.0))) + 1
    breaks = np.minimum(2.0, step[:, None] * (2.0 ** np.arange(levels + 1) - 1.0))
    # only the pieces of non-zero length: the breaks stop at the element's far end (2), so
    # the last levels of most pairs are empty (a third of the points at uniform spacing)
    pair, piece = np.nonzero(breaks[:, 1:] > breaks[:, :-1])
    lo, hi = breaks[pair, piece], breaks[pair, piece + 1]
    t = lo[:, None] + (hi - lo)[:, None] * t_smooth
    w = (hi - lo)[:, None] * w_smooth
    side = near_end[pair, None]
    xs, jac, values = _map_at(face, e[pair], side - side * t)
    f = (jac * w)[..., None] * values
    at = xk[pair, None]
    log_piece = np.einsum("pg,pga->pa", np.log(np.abs(xs - at) / datum), f)
    sign_piece = np.einsum("pg,pga->pa", np.sign(at - xs), f)
    starts = np.flatnonzero(np.concatenate([[True], pair[1:] != pair[:-1]]))  # every pair has one
    return np.add.reduceat(log_piece, starts), np.add.reduceat(sign_piece, starts)


def _map_at(face: Basis, e: np.ndarray, local: np.ndarray):
    """_element_map at local coordinates (m, g) of elements e (m,), shaped (m, g, ...)."""
    m, g = local.shape
    xs, jac, values = _element_map(face, np.repeat(e, g), local.ravel())
    return xs.reshape(m, g), jac.reshape(m, g), values.reshape(m, g, -1)
