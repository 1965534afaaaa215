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

import math

import attrs
import numpy as np

from fretbem.basis import Basis
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

#: Gauss-Legendre points per (sub)interval and Gauss-log points per singular piece
SMOOTH_POINTS = 12
LOG_POINTS = 12


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
    """Projected position x(xi) and |dx/dxi| with the shape-function values."""
    m = face.map(elements, local)
    return m.points[:, 0], np.abs(m.tangents[:, 0]), m.values


def check_face(face: Basis) -> None:
    """Require x to run monotonically along the face: it is the graph of a surface profile."""
    rule = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    elements = np.repeat(np.arange(face.n_elements), rule.points.size)
    local = np.tile(rule.points, face.n_elements)
    dx = face.map(elements, local).tangents[:, 0]
    if not (np.all(dx > 0) or np.all(dx < 0)):
        raise HalfPlaneFaceError(
            "a half-plane face must run monotonically in x (it is the graph y(x) of the "
            "surface profile over the half-plane's straight surface), but x turns back along "
            "this face; describe the face as a curve whose x always increases or decreases"
        )


def _invert(face: Basis, elements: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Local coordinate where x(xi) = target on each element (bisection: x is monotone)."""
    lo = np.full(len(elements), -1.0)
    hi = np.full(len(elements), 1.0)
    increasing = _element_map(face, elements, hi)[0] > _element_map(face, elements, lo)[0]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        above = _element_map(face, elements, mid)[0] > targets
        move_hi = above == increasing
        hi = np.where(move_hi, mid, hi)
        lo = np.where(move_hi, lo, mid)
    return 0.5 * (lo + hi)


def surface_integrals(face: Basis, x, datum: float = 1.0) -> SurfaceIntegrals:
    """ln and sign integrals of the face's shape functions for field points ``x`` on the surface.

    Elements at least their own length away use one Gauss-Legendre rule (vectorised); a
    nearer element is split at the field point, with a Gauss-log rule for ln t on each piece,
    or graded geometrically toward the field point when it lies just outside.
    """
    x = np.asarray(x, dtype=float).ravel()
    rule = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    n_el, n_g = face.n_elements, rule.points.size
    elements = np.repeat(np.arange(n_el), n_g)
    local = np.tile(rule.points, n_el)
    xq, jac, values = _element_map(face, elements, local)
    xq, jac = xq.reshape(n_el, n_g), jac.reshape(n_el, n_g)
    weights = (jac * rule.weights).reshape(n_el, n_g)
    values = values.reshape(n_el, n_g, -1)
    ends = _element_map(face, np.repeat(np.arange(n_el), 2), np.tile([-1.0, 1.0], n_el))[0]
    ends = ends.reshape(n_el, 2)
    left, right = ends.min(axis=1), ends.max(axis=1)
    length = right - left
    distance = np.maximum(np.maximum(left[None, :] - x[:, None], x[:, None] - right[None, :]), 0)
    # far elements: one rule, all field points at once
    log_el = np.einsum(
        "keg,eg,ega->kea", np.log(np.abs(x[:, None, None] - xq[None]) / datum), weights, values
    )
    moments = np.einsum("eg,ega->ea", weights, values)
    sign_el = np.sign(x[:, None] - 0.5 * (left + right)[None, :])[:, :, None] * moments[None]
    near_k, near_e = np.nonzero(distance < length[None, :])
    if near_k.size:
        log_el[near_k, near_e], sign_el[near_k, near_e] = _near(
            face, near_e, x[near_k], datum, ends[near_e]
        )
    n_functions = face.n_functions
    log = np.zeros((len(x), n_functions))
    sign = np.zeros((len(x), n_functions))
    for e in range(n_el):
        log[:, face.connectivity[e]] += log_el[:, e]
        sign[:, face.connectivity[e]] += sign_el[:, e]
    return SurfaceIntegrals(log, sign)


def _near(face: Basis, e: np.ndarray, xk: np.ndarray, datum: float, ends: np.ndarray):
    """Integrals over elements ``e`` for field points ``xk`` on or just beside them.

    ``ends`` (m, 2) holds x at local -1 and +1 of each element.
    """
    log_out = np.zeros((len(e), face.n_local))
    sign_out = np.zeros((len(e), face.n_local))
    length = np.abs(ends[:, 1] - ends[:, 0])
    tol = 1e-12 * length
    inside = (xk >= ends.min(axis=1) - tol) & (xk <= ends.max(axis=1) + tol)
    if inside.any():
        log_out[inside], sign_out[inside] = _split(face, e[inside], xk[inside], datum, ends[inside])
    outside = ~inside
    if outside.any():
        log_out[outside], sign_out[outside] = _graded(
            face, e[outside], xk[outside], datum, ends[outside]
        )
    return log_out, sign_out


def _split(face: Basis, e, xk, datum, ends):
    """Elements containing their field point: split there, ln t by the Gauss-log rule."""
    tol = 1e-12 * np.abs(ends[:, 1] - ends[:, 0])
    star = _invert(face, e, xk)
    star = np.where(np.abs(xk - ends[:, 0]) <= tol, -1.0, star)
    star = np.where(np.abs(xk - ends[:, 1]) <= tol, 1.0, star)
    smooth = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    log_rule = QuadratureRule.gauss_log(LOG_POINTS)
    t_smooth, w_smooth = 0.5 * (smooth.points + 1.0), 0.5 * smooth.weights
    m = len(e)
    log_sum = np.zeros((m, face.n_local))
    sign_sum = np.zeros((m, face.n_local))
    for end in (-1.0, 1.0):
        h = end - star
        empty = np.abs(h) < 1e-14
        h = np.where(empty, 0.0, h)
        # xi = star + h t, t in [0, 1]: ln|x - xk| = ln t + ln(|x - xk| / t)
        xs, jac, values = _map_at(face, e, star[:, None] + h[:, None] * t_smooth[None])
        r_over_t = np.where(empty[:, None], 1.0, np.abs(xs - xk[:, None])) / t_smooth
        f = (jac * np.abs(h)[:, None] * w_smooth)[..., None] * values
        log_sum += np.einsum("mg,mga->ma", np.log(r_over_t / datum), f)
        sign_sum += np.einsum("mg,mga->ma", np.sign(xk[:, None] - xs), f)
        _, jl, vl = _map_at(face, e, star[:, None] + h[:, None] * log_rule.points[None])
        log_sum -= np.einsum("mg,mga->ma", jl * np.abs(h)[:, None] * log_rule.weights, vl)
    return log_sum, sign_sum


def _graded(face: Basis, e, xk, datum, ends):
    """Field points just outside: pieces growing geometrically from the near end, each as
    long as its distance to the field point, so one Gauss-Legendre rule resolves ln on each."""
    smooth = QuadratureRule.gauss_legendre(SMOOTH_POINTS)
    t_smooth, w_smooth = 0.5 * (smooth.points + 1.0), 0.5 * smooth.weights
    to_end = np.abs(xk[:, None] - ends)
    near_end = np.where(to_end[:, 0] < to_end[:, 1], -1.0, 1.0)
    step = 2.0 * to_end.min(axis=1) / np.abs(ends[:, 1] - ends[:, 0])  # gap in local units
    levels = int(np.ceil(np.log2(2.0 / step.min() + 1.0))) + 1
    breaks = np.minimum(2.0, step[:, None] * (2.0 ** np.arange(levels + 1) - 1.0))
    lo, hi = breaks[:, :-1], breaks[:, 1:]
    t = (lo[..., None] + (hi - lo)[..., None] * t_smooth).reshape(len(e), -1)
    w = ((hi - lo)[..., None] * w_smooth).reshape(len(e), -1)
    xs, jac, values = _map_at(face, e, near_end[:, None] - near_end[:, None] * t)
    f = (jac * w)[..., None] * values
    log_sum = np.einsum("mg,mga->ma", np.log(np.abs(xs - xk[:, None]) / datum), f)
    sign_sum = np.einsum("mg,mga->ma", np.sign(xk[:, None] - xs), f)
    return log_sum, sign_sum


def _map_at(face: Basis, e: np.ndarray, local: np.ndarray):
    """_element_map at local coordinates (m, g) of elements e (m,), shaped (m, g, ...)."""
    m, g = local.shape
    xs, jac, values = _element_map(face, np.repeat(e, g), local.ravel())
    return xs.reshape(m, g), jac.reshape(m, g), values.reshape(m, g, -1)
