"""Kelvin stress kernels of 2D elastostatics: the derivatives in Somigliana's stress identity.

sigma_ij(x) = int D_kij(x, y) t_k(y) dGamma(y) - int S_kij(x, y) u_k(y) dGamma(y)

for an interior point x; r = y - x (field minus source, as :mod:`fretbem.bem.kernels`), n the
unit outward normal at y. Plane-strain form; plane stress uses nu / (1 + nu) (the material's
``kernel_nu``) with the same shear modulus. Formulas: C. A. Brebbia and J. Dominguez,
Boundary Elements: An Introductory Course (1992), ch. 5. Components are returned in the order
c = (xx, yy, xy); all functions are plain arithmetic so the compiled loops reuse them.
"""

from __future__ import annotations

import numpy as np

#: (i, j) of the stress components xx, yy, xy
COMPONENTS = ((0, 0), (1, 1), (0, 1))


def _delta(i: int, j: int) -> float:
    return 1.0 if i == j else 0.0


def stress_kernels(rx, ry, nx, ny, nu: float, shear_modulus: float):
    """D and S, each shape (..., 2, 3) [k, c]: stress c at x from a unit traction (D) or
    displacement (S) in direction k at y. ``rx, ry`` = y - x; ``nx, ny`` the normal at y."""
    r2 = rx * rx + ry * ry
    inv_r = 1.0 / np.sqrt(r2)
    g = (rx * inv_r, ry * inv_r)
    n = (nx, ny)
    dn = g[0] * nx + g[1] * ny
    a = 1.0 - 2.0 * nu
    d_scale = inv_r / (4.0 * np.pi * (1.0 - nu))
    s_scale = shear_modulus / (2.0 * np.pi * (1.0 - nu)) * inv_r * inv_r
    shape = np.shape(r2)
    d = np.empty((*shape, 2, 3))
    s = np.empty((*shape, 2, 3))
    for k in range(2):
        for c, (i, j) in enumerate(COMPONENTS):
            d[..., k, c] = d_scale * (
                a * (_delta(k, i) * g[j] + _delta(k, j) * g[i] - _delta(i, j) * g[k])
                + 2.0 * g[i] * g[j] * g[k]
            )
            s[..., k, c] = s_scale * (
                2.0
                * dn
                * (
                    a * _delta(i, j) * g[k]
                    + nu * (_delta(i, k) * g[j] + _delta(j, k) * g[i])
                    - 4.0 * g[i] * g[j] * g[k]
                )
                + 2.0 * nu * (n[i] * g[j] * g[k] + n[j] * g[i] * g[k])
                + a * (2.0 * n[k] * g[i] * g[j] + n[j] * _delta(i, k) + n[i] * _delta(j, k))
                - (1.0 - 4.0 * nu) * n[k] * _delta(i, j)
            )
    return d, s
