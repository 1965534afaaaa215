"""Interior stresses of a half-plane body: Flamant line loads integrated over the face.

The traction interpolated on the discretised face (its shape functions over the projected
abscissa, as the half-plane surface operator uses them) is integrated against the Flamant
line-load stresses (Johnson, Contact Mechanics, 1985, eqs. 2.15 and 2.21). Near and on the
surface the local traction value is subtracted and added back through the closed-form
stresses of a uniform strip load over the whole face,

    sigma(x, z) = int K(x - s, z) [tau(s) - tau(x)] ds + tau(x) int_face K(x - s, z) ds,

so the integrand stays bounded as z -> 0 and the surface limit (sigma_yy = -p, sigma_xy = q,
sigma_xx = -p - (2 / pi) PV int q(s) / (x - s) ds) comes out of the same formula. The
evaluation is linear in the traction coefficients: a (3 m, 2 N) matrix built once.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.basis import Basis
from fretbem.errors import StressInputError
from fretbem.numerics.graded import graded_rule
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.numerics.scatter import added_at

#: Gauss points per element (far) and per graded piece (near)
FAR_POINTS = 8
GRADED_POINTS = 8
GRADED_RATIO = 0.3


def _strip_primitives(u, z):
    """Antiderivatives in u of the Flamant kernels' u-z polynomials (u = x - s, z >= 0).

    Returns F[name] for the integrands u^2 z, z^3, u z^2, u^3 over (u^2 + z^2)^2.
    """
    r2 = u * u + z * z
    with np.errstate(divide="ignore", invalid="ignore"):
        angle = np.where(z > 0, np.arctan2(u, z), 0.5 * np.pi * np.sign(u))
        ratio = np.where(r2 > 0, u * z / np.where(r2 > 0, r2, 1.0), 0.0)
        z2ratio = np.where(r2 > 0, z * z / np.where(r2 > 0, r2, 1.0), 1.0)
        log = np.log(np.where(r2 > 0, r2, 1.0))
    return {
        "uuz": 0.5 * (angle - ratio),
        "zzz": 0.5 * (angle + ratio),
        "uzz": -0.5 * z2ratio,
        "uuu": 0.5 * log + 0.5 * z2ratio,
    }


def strip_stress(x, depth, s1: float, s2: float, *, normal: float, tangential: float):
    """Stresses (..., 3) [sxx, syy, sxy] of a uniform pressure ``normal`` and shear
    ``tangential`` (+x) on s1 < s < s2 of a lower half-plane at (x, depth)."""
    x, z = np.broadcast_arrays(np.asarray(x, float), np.asarray(depth, float))
    hi = _strip_primitives(x - s1, z)
    lo = _strip_primitives(x - s2, z)
    f = {key: hi[key] - lo[key] for key in hi}
    k = -2.0 / np.pi
    sxx = k * (normal * f["uuz"] + tangential * f["uuu"])
    syy = k * (normal * f["zzz"] + tangential * f["uzz"])
    txz = k * (normal * f["uzz"] + tangential * f["uuz"])
    return np.stack([sxx, syy, -txz], axis=-1)


def _face_x(face: Basis, elements, local):
    m = face.map(elements, local)
    return m.points[:, 0], np.abs(m.tangents[:, 0]), m.values


def _locate(face: Basis, x: np.ndarray):
    """Element and local coordinate where the face's abscissa equals x (bisection), and a
    mask of the points whose x lies on the face."""
    n_el = face.n_elements
    ends = _face_x(face, np.repeat(np.arange(n_el), 2), np.tile([-1.0, 1.0], n_el))[0]
    ends = ends.reshape(n_el, 2)
    left, right = ends.min(axis=1), ends.max(axis=1)
    inside = (x >= left.min()) & (x <= right.max())
    element = np.clip(np.searchsorted(np.sort(left), x, side="right") - 1, 0, n_el - 1)
    order = np.argsort(left)
    element = order[element]
    lo = np.full(len(x), -1.0)
    hi = np.full(len(x), 1.0)
    increasing = ends[element, 1] > ends[element, 0]
    for _ in range(55):
        mid = 0.5 * (lo + hi)
        above = _face_x(face, element, mid)[0] > x
        move_hi = above == increasing
        hi = np.where(move_hi, mid, hi)
        lo = np.where(move_hi, lo, mid)
    return element, 0.5 * (lo + hi), inside, left, right


def halfplane_stress_matrix(face: Basis, x, depth, *, chunk: int = 512) -> np.ndarray:
    """Matrix (m, 3, N, 2): stresses [sxx, syy, sxy] of a lower half-plane at (x, depth)
    per unit traction coefficient (component x or y of the traction ON the body; the
    pressure is -t_y) of the face's N shape functions."""
    x = np.asarray(x, float).ravel()
    z = np.asarray(depth, float).ravel()
    if np.any(z < 0) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(z))):
        raise StressInputError("half-plane points need finite x and depth >= 0 (inside the body)")
    n_el, n_fun, n_loc = face.n_elements, face.n_functions, face.n_local
    element, local, on_face, left, right = _locate(face, x)
    vals = face.shape_functions(element, local)[0]
    rows = np.flatnonzero(on_face)
    values_at = added_at(
        (len(x), n_fun), (rows[:, None], face.connectivity[element[rows]]), vals[rows]
    )
    lo_face, hi_face = left.min(), right.max()
    out = np.zeros((len(x), 3, n_fun, 2))
    # the local value tau(x) times (exact strip over the whole face - the same integral by
    # the quadrature below): the subtraction, written as a correction of the plain rule
    whole = np.zeros((len(x), 3, 2))
    whole[:, :, 0] = strip_stress(x, z, lo_face, hi_face, normal=0.0, tangential=1.0)
    whole[:, :, 1] = -strip_stress(x, z, lo_face, hi_face, normal=1.0, tangential=0.0)

    rule = QuadratureRule.gauss_legendre(FAR_POINTS)
    el = np.repeat(np.arange(n_el), rule.points.size)
    xq, jac, phi = _face_x(face, el, np.tile(rule.points, n_el))
    xq = xq.reshape(n_el, -1)
    w = (jac * np.tile(rule.weights, n_el)).reshape(n_el, -1)
    phi = phi.reshape(n_el, -1, n_loc)
    length = right - left
    horizontal = np.maximum(np.maximum(left[None] - x[:, None], x[:, None] - right[None]), 0.0)
    near = np.hypot(horizontal, z[:, None]) < length[None]
    for start in range(0, len(x), chunk):
        r = slice(start, min(start + chunk, len(x)))
        u = x[r, None, None] - xq[None]
        zz = np.broadcast_to(z[r, None, None], u.shape)
        with np.errstate(divide="ignore", invalid="ignore"):
            kp = np.nan_to_num(flamant_stress_safe(u, zz, 1.0, 0.0), posinf=0.0, neginf=0.0)
            kq = np.nan_to_num(flamant_stress_safe(u, zz, 0.0, 1.0), posinf=0.0, neginf=0.0)
        ww = w[None] * ~near[r][:, :, None]
        for kern, comp, sign in ((kq, 0, 1.0), (kp, 1, -1.0)):
            whole[r, :, comp] -= sign * np.einsum("peqc,peq->pc", kern, ww)
            block = sign * np.einsum("peqc,peq,eqa->pcea", kern, ww, phi)
            for a in range(n_loc):
                _scatter(out, r, face.connectivity[:, a], comp, block[:, :, :, a])
    # near pairs: graded toward the point's abscissa on the element
    p_idx, e_idx = np.nonzero(near)
    if p_idx.size:
        xe_lo = _face_x(face, e_idx, np.full(len(e_idx), -1.0))[0]
        xe_hi = _face_x(face, e_idx, np.full(len(e_idx), 1.0))[0]
        frac = np.clip((x[p_idx] - xe_lo) / (xe_hi - xe_lo), 0.0, 1.0)
        centre = 2.0 * frac - 1.0
        scale = 0.5 * np.abs(xe_hi - xe_lo)
        dist_local = np.maximum(np.hypot(horizontal[p_idx, e_idx], z[p_idx]) / scale, 1e-9)
        loc, wt = graded_rule(centre, dist_local, GRADED_POINTS, GRADED_RATIO)
        q = loc.shape[1]
        xs, js, ph = _face_x(face, np.repeat(e_idx, q), loc.ravel())
        xs, ws, ph = xs.reshape(-1, q), (js.reshape(-1, q) * wt), ph.reshape(-1, q, n_loc)
        u = x[p_idx, None] - xs
        zz = np.broadcast_to(z[p_idx, None], u.shape)
        with np.errstate(divide="ignore", invalid="ignore"):
            kp = np.nan_to_num(flamant_stress_safe(u, zz, 1.0, 0.0), posinf=0.0, neginf=0.0)
            kq = np.nan_to_num(flamant_stress_safe(u, zz, 0.0, 1.0), posinf=0.0, neginf=0.0)
        cols = face.connectivity[e_idx]
        for kern, comp, sign in ((kq, 0, 1.0), (kp, 1, -1.0)):
            np.add.at(whole[:, :, comp], p_idx, -sign * np.einsum("pqc,pq->pc", kern, ws))
            block = sign * np.einsum("pqc,pq,pqa->pca", kern, ws, ph)
            for a in range(n_loc):
                np.add.at(out, (p_idx, slice(None), cols[:, a], comp), block[:, :, a])
    out += whole[:, :, None, :] * values_at[:, None, :, None]
    return out


def flamant_stress_safe(u, z, normal: float, tangential: float) -> np.ndarray:
    """Flamant stresses (..., 3) allowing r = 0 (returns nan there; callers weight it 0)."""
    r2 = u * u + z * z
    k = -2.0 / (np.pi * r2 * r2)
    sxx = k * (normal * u * u * z + tangential * u**3)
    syy = k * (normal * z**3 + tangential * u * z * z)
    txz = k * (normal * u * z * z + tangential * u * u * z)
    return np.stack([sxx, syy, -txz], axis=-1)


def _scatter(out, rows: slice, columns: np.ndarray, comp: int, block: np.ndarray) -> None:
    """out[rows, c, columns[e], comp] += block[p, c, e] (repeated columns accumulate)."""
    n_fun = out.shape[2]
    e = block.shape[2]
    onehot = np.zeros((e, n_fun))
    onehot[np.arange(e), columns] = 1.0
    out[rows, :, :, comp] += block @ onehot


@attrs.frozen(eq=False)
class HalfPlaneStressOperator:
    """Half-plane stresses as a matrix over the face traction coefficients, plus the bulk."""

    matrix: np.ndarray  # (m, 3, N, 2)
    collocation: np.ndarray  # E: coefficients -> node values
    mirror: bool
    nu: float
    plane_stress: bool
    bulk: bool

    @classmethod
    def of(cls, model, points: np.ndarray) -> HalfPlaneStressOperator:
        surface = model.surface
        face_y = surface.points[:, 1]
        upper = model.side == "upper"
        level = face_y.min() if upper else face_y.max()
        depth = (points[:, 1] - level) if upper else (level - points[:, 1])
        if np.any(depth < -1e-9 * max(np.ptp(surface.points[:, 0]), 1.0)):
            i = int(np.argmin(depth))
            raise StressInputError(
                f"point {points[i].tolist()} lies outside the half-plane "
                f"({'above' if not upper else 'below'} its surface y = {level:g})"
            )
        matrix = halfplane_stress_matrix(surface.face, points[:, 0], np.maximum(depth, 0.0))
        return cls(
            matrix,
            surface.collocation_matrix,
            upper,
            model.material.nu,
            model.material.plane_stress,
            "bulk" in model.load_names,
        )

    def evaluate(self, solution) -> np.ndarray:
        tractions = np.asarray(solution.tractions, float)
        if self.mirror:  # the upper body is the lower one reflected in its surface line
            tractions = tractions * np.array([1.0, -1.0])
        coefficients = np.linalg.solve(self.collocation, tractions)
        stress = np.einsum("pcnk,nk->pc", self.matrix, coefficients)
        if self.mirror:
            stress[:, 2] *= -1.0
        if self.bulk:
            stress[:, 0] += float(solution.loads.get("bulk", 0.0))
        szz = 0.0 if self.plane_stress else self.nu * (stress[:, 0] + stress[:, 1])
        return np.column_stack([stress, np.broadcast_to(szz, len(stress))])
