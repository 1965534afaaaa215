"""Stress on the boundary from the boundary data: traction and tangential displacement
derivative, Hooke's law in the local (tangent, normal) frame.

With s the unit tangent, n the unit outward normal: sigma_nn = t . n, sigma_ns = t . s from
the traction; the tangential strain eps_ss = s . du/ds gives, in plane strain,
sigma_ss = (2 mu eps_ss + nu sigma_nn) / (1 - nu) (plane stress: nu -> nu / (1 + nu)).
Every function is linear in the data, so the same code builds evaluation matrices.
"""

from __future__ import annotations

import numpy as np


def boundary_state(
    values: np.ndarray,
    derivatives: np.ndarray,
    tangents: np.ndarray,
    traction: np.ndarray,
    displacement: np.ndarray,
    *,
    shear_modulus: float,
    nu: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stress (p, 2, 2, ...), displacement (p, 2, ...) and displacement gradient
    du_i/dx_j (p, 2, 2, ...) at boundary points.

    ``values``, ``derivatives``: shape functions and d/d(local) at the points (p, n_local);
    ``tangents``: dx/d(local) (p, 2); ``traction``, ``displacement``: the element's local
    coefficients (p, n_local, 2, ...) (trailing axes batch several data sets); ``nu`` the
    kernel (plane-strain) Poisson ratio.
    """
    jac = np.linalg.norm(tangents, axis=-1)
    s = tangents / jac[:, None]
    n = np.stack([s[:, 1], -s[:, 0]], axis=-1)
    extra = traction.ndim - 3
    expand = (slice(None), slice(None)) + (None,) * extra

    def along(vec):  # (p, 2) -> (p, 2, 1, ...) for broadcasting against (p, 2, ...)
        return vec[expand]

    t0 = np.einsum("pa,pak...->pk...", values, traction)
    u0 = np.einsum("pa,pak...->pk...", values, displacement)
    du_ds = np.einsum("pa,pak...->pk...", derivatives, displacement)
    du_ds = du_ds / jac.reshape(-1, *([1] * (du_ds.ndim - 1)))
    s_nn = np.sum(along(n) * t0, axis=1)
    s_ns = np.sum(along(s) * t0, axis=1)
    e_ss = np.sum(along(s) * du_ds, axis=1)
    s_ss = (2.0 * shear_modulus * e_ss + nu * s_nn) / (1.0 - nu)

    def outer(a, b):  # (p, 2) x (p, 2) -> (p, 2, 2, 1...)
        return (a[:, :, None] * b[:, None, :])[(slice(None),) * 3 + (None,) * extra]

    stress = (
        outer(s, s) * s_ss[:, None, None]
        + outer(n, n) * s_nn[:, None, None]
        + (outer(s, n) + outer(n, s)) * s_ns[:, None, None]
    )
    trace = stress[:, 0, 0] + stress[:, 1, 1]
    eye = np.eye(2)[(None, slice(None), slice(None)) + (None,) * extra]
    strain = (stress - nu * trace[:, None, None] * eye) / (2.0 * shear_modulus)
    # rotation from the tangential derivative: du/ds = (strain + W) s, W = [[0, -w], [w, 0]]
    strain_s = np.einsum("pij...,pj->pi...", strain, s)
    omega = -np.sum(along(n) * (du_ds - strain_s), axis=1)
    rotation = np.zeros_like(strain)
    rotation[:, 0, 1] = -omega
    rotation[:, 1, 0] = omega
    return stress, u0, strain + rotation
