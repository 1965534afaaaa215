"""Closed-form stresses below a 2D Hertzian contact: McEwen, Smith-Liu, Cattaneo-Mindlin.

Half-plane theory, elastically similar bodies. Every function returns the stress of the
*lower* body, whose surface is y = 0, at points (x, depth) with depth = -y >= 0, in the global
frame, as an array (..., 4) = [sigma_xx, sigma_yy, sigma_xy, sigma_zz] in the units of the
tractions. Tractions on that body: the pressure p >= 0 pushes into it (-y); the shear q acts
on it in +x (the shear the pad exerts on the specimen). sigma_zz is nu (sigma_xx + sigma_yy)
in plane strain (the whole in-plane stress, bulk stress included: the body's out-of-plane
strain is zero) and 0 in plane stress.

Sources: E. McEwen, "Stresses in elastic cylinders in contact along a generatrix", Phil.
Mag. 40 (1949) 454-459 (pressure); F. W. Smith and C. K. Liu, "Stresses due to tangential and
normal loads on an elastic solid", J. Appl. Mech. 20 (1953) 157-166 (shear); D. A. Hills and
D. Nowell, Mechanics of Fretting Fatigue (Kluwer, 1994), ch. 5 (superposition and offset).
With these signs a positive shear puts the surface tension peak at the edge x = -a: the
material behind the pushed surface is stretched.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .errors import StressInputError

__all__ = [
    "cattaneo_mindlin_stress",
    "elliptical_pressure_stress",
    "elliptical_shear_stress",
    "flamant_stress",
    "surface_sigma_xx",
]


def _inputs(x: ArrayLike, depth: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    x, depth = np.broadcast_arrays(np.asarray(x, float), np.asarray(depth, float))
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(depth))):
        raise StressInputError("x and depth must be finite numbers")
    if np.any(depth < 0):
        raise StressInputError(
            f"depth must be >= 0 (depth = -y below the surface y = 0), got min {depth.min():g}"
        )
    return x, depth


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (value > 0 and np.isfinite(value)):
        raise StressInputError(f"{name} must be a finite number > 0, got {value!r}")
    return value


def _mn(x: np.ndarray, z: np.ndarray, a: float):
    """McEwen's m, n (sign m = sign z, sign n = sign x) and 1 / (m^2 + n^2) (0 at the edge)."""
    big_a = a * a - x * x + z * z
    root = np.sqrt(big_a * big_a + 4.0 * x * x * z * z)
    m = np.sqrt(np.maximum(0.5 * (root + big_a), 0.0))
    n = np.sign(x) * np.sqrt(np.maximum(0.5 * (root - big_a), 0.0))
    m2n2 = m * m + n * n
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(m2n2 > 0.0, 1.0 / np.where(m2n2 > 0.0, m2n2, 1.0), 0.0)
    return m, n, inv


def _pack(sxx, syy, sxy, nu: float, plane_strain: bool) -> np.ndarray:
    szz = nu * (sxx + syy) if plane_strain else np.zeros_like(sxx)
    return np.stack([sxx, syy, sxy, szz], axis=-1)


def elliptical_pressure_stress(
    x: ArrayLike,
    depth: ArrayLike,
    *,
    a: float,
    p0: float,
    centre: float = 0.0,
    nu: float,
    plane_strain: bool = True,
) -> np.ndarray:
    """McEwen: pressure p0 sqrt(1 - (x - centre)^2 / a^2) on |x - centre| < a."""
    x, z = _inputs(x, depth)
    a = _positive("a", a)
    m, n, inv = _mn(x - centre, z, a)
    k = p0 / a
    sxx = -k * (m * (1.0 + (z * z + n * n) * inv) - 2.0 * z)
    szz_ = -k * m * (1.0 - (z * z + n * n) * inv)
    txz = -k * n * (m * m - z * z) * inv
    return _pack(sxx, szz_, -txz, nu, plane_strain)


def elliptical_shear_stress(
    x: ArrayLike,
    depth: ArrayLike,
    *,
    b: float,
    q0: float,
    centre: float = 0.0,
    nu: float,
    plane_strain: bool = True,
) -> np.ndarray:
    """Smith-Liu: shear q0 sqrt(1 - (x - centre)^2 / b^2) in +x on |x - centre| < b."""
    x, z = _inputs(x, depth)
    b = _positive("b", b)
    s = x - centre
    m, n, inv = _mn(s, z, b)
    k = q0 / b
    sxx = k * (n * (2.0 - (z * z - m * m) * inv) - 2.0 * s)
    szz_ = -k * n * (m * m - z * z) * inv
    txz = -k * (m * (1.0 + (z * z + n * n) * inv) - 2.0 * z)
    return _pack(sxx, szz_, -txz, nu, plane_strain)


def cattaneo_mindlin_stress(
    x: ArrayLike,
    depth: ArrayLike,
    *,
    a: float,
    p0: float,
    f: float,
    c: float,
    e: float = 0.0,
    sigma_bulk: float = 0.0,
    nu: float,
    plane_strain: bool = True,
) -> np.ndarray:
    """Cattaneo-Mindlin (with the Nowell-Hills offset e): Hertz pressure, shear f p0 over a,
    minus f p0 c / a over the stick zone |x - e| < c, plus ``sigma_bulk`` on sigma_xx.

    ``f`` may be negative for a shear in -x (e.g. the reversed step); c = a gives no shear.
    """
    a = _positive("a", a)
    c = float(c)
    if not (0.0 <= c <= a) or abs(float(e)) + c > a * (1.0 + 1e-12):
        raise StressInputError(
            f"the stick zone |x - e| < c must lie inside the contact: need 0 <= c <= a and "
            f"|e| + c <= a, got a={a:g}, c={c:g}, e={float(e):g}"
        )
    out = elliptical_pressure_stress(x, depth, a=a, p0=p0, nu=nu, plane_strain=plane_strain)
    out = out + elliptical_shear_stress(x, depth, b=a, q0=f * p0, nu=nu, plane_strain=plane_strain)
    if c > 0.0:
        out = out - elliptical_shear_stress(
            x, depth, b=c, q0=f * p0 * c / a, centre=e, nu=nu, plane_strain=plane_strain
        )
    out[..., 0] += sigma_bulk
    if plane_strain:
        out[..., 3] += nu * sigma_bulk
    return out


def surface_sigma_xx(
    x: ArrayLike,
    *,
    a: float,
    p0: float,
    f: float,
    c: float,
    e: float = 0.0,
    sigma_bulk: float = 0.0,
) -> np.ndarray:
    """sigma_xx on the surface y = 0 of the Cattaneo-Mindlin / Nowell-Hills field."""
    return cattaneo_mindlin_stress(
        x, 0.0, a=a, p0=p0, f=f, c=c, e=e, sigma_bulk=sigma_bulk, nu=0.0, plane_strain=False
    )[..., 0]


def flamant_stress(
    x: ArrayLike,
    depth: ArrayLike,
    *,
    normal: float = 0.0,
    tangential: float = 0.0,
    nu: float,
    plane_strain: bool = True,
) -> np.ndarray:
    """Flamant: line loads at the origin, ``normal`` pushing into the body and ``tangential``
    in +x (force per unit thickness); singular at the origin (Johnson, Contact Mechanics,
    1985, eq. 2.15 and 2.21)."""
    x, z = _inputs(x, depth)
    r2 = x * x + z * z
    if np.any(r2 == 0.0):
        raise StressInputError("the Flamant field is singular at the load point (0, 0)")
    k = -2.0 / (np.pi * r2 * r2)
    sxx = k * (normal * x * x * z + tangential * x**3)
    szz_ = k * (normal * z**3 + tangential * x * z * z)
    txz = k * (normal * x * z * z + tangential * x * x * z)
    return _pack(sxx, szz_, -txz, nu, plane_strain)
