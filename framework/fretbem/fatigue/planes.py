"""Material planes in 3D and the linear maps from the stress components to the plane's stresses.

In the 2D (plane strain or plane stress) models the stress tensor has the form
[[sxx, sxy, 0], [sxy, syy, 0], [0, 0, szz]], so z is always a principal direction. A plane
normal is n = (sin(psi) cos(theta), sin(psi) sin(theta), cos(psi)); mirror symmetry in z and
n ~ -n reduce the search to theta in [0, 180) degrees and psi in [0, 90] degrees, where psi = 90
is the in-plane family (planes that contain the z axis, the only ones a 2D search sees).
With e = (cos theta, sin theta, 0), u1 = cos(psi) e - sin(psi) e_z and u2 = (-sin theta,
cos theta, 0) as the two shear directions on the plane,

    sigma_n = sin^2(psi) sigma_ee + cos^2(psi) szz
    tau_1   = sin(psi) cos(psi) (sigma_ee - szz)
    tau_2   = sin(psi) tau_e

with sigma_ee and tau_e the in-plane normal and shear stress on direction theta. Each is a
fixed linear combination of (sxx, syy, sxy, szz): one matrix product gives all planes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plane_grid", "projection"]


def projection(theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Coefficients (3, ..., 4) mapping (sxx, syy, sxy, szz) to (sigma_n, tau_1, tau_2)."""
    theta = np.asarray(theta, dtype=float)
    psi = np.asarray(psi, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    sp, cp = np.sin(psi), np.cos(psi)
    zero = np.zeros_like(theta * psi)
    ee = np.stack([c * c, s * s, 2 * c * s, zero], axis=-1)  # sigma_ee
    te = np.stack([-c * s, c * s, c * c - s * s, zero], axis=-1)  # tau_e
    zz = np.stack([zero, zero, zero, zero + 1.0], axis=-1)
    sp2 = (sp * sp)[..., None]
    cp2 = (cp * cp)[..., None]
    spcp = (sp * cp)[..., None]
    normal = sp2 * ee + cp2 * zz
    tau1 = spcp * (ee - zz)
    tau2 = sp[..., None] * te
    return np.stack([normal, tau1, tau2], axis=0)


def plane_grid(*, in_plane_only: bool, theta_step_deg: float, psi_step_deg: float):
    """Angles (theta, psi) in radians of a search grid, without the duplicates at psi = 0.

    The full grid covers the quarter sphere that represents every plane once; the in-plane
    grid is the psi = 90 degree row only.
    """
    thetas = np.deg2rad(np.arange(0.0, 180.0, theta_step_deg))
    if in_plane_only:
        return thetas, np.full_like(thetas, np.pi / 2)
    n_psi = max(1, round(90.0 / psi_step_deg))
    psis = np.deg2rad(np.linspace(90.0, 0.0, n_psi + 1))[:-1]
    theta, psi = np.meshgrid(thetas, psis, indexing="ij")
    theta = np.concatenate([theta.ravel(), [0.0]])
    psi = np.concatenate([psi.ravel(), [0.0]])
    return theta, psi
