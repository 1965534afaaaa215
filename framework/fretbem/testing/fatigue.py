"""Stress histories for testing critical-plane searches.

Seeded, so a test sees the same history on every run: a fretting contact's cycle at random
points below it, and random non-proportional histories in plane strain.
"""

from __future__ import annotations

import numpy as np

from fretbem.fatigue import METHODS, CattaneoMindlinCycle, last_full_reversal
from fretbem.fatigue import critical_plane as cp

__all__ = ["contact_stress_history", "in_plane_scan", "random_stress_history"]


def contact_stress_history(
    n: int = 40, seed: int = 3, *, depth: float = 0.3, steps_per_branch: int = 3, nu: float = 0.342
) -> np.ndarray:
    """The Cattaneo-Mindlin / Nowell-Hills cycle (a 0.5 mm, p0 300 MPa, f 0.6, Q/fP 0.5, bulk
    80 MPa) over its last full reversal at ``n`` random points within ``depth`` mm below the
    contact: (steps, n, 4) stresses [sxx, syy, sxy, szz] in MPa."""
    cm = CattaneoMindlinCycle(
        a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5, sigma_bulk_max=80.0, nu=nu,
        steps_per_branch=steps_per_branch,
    )  # fmt: skip
    rng = np.random.default_rng(seed)
    points = np.stack([rng.uniform(-0.75, 0.75, n), rng.uniform(0.0, depth, n)], axis=1)
    return cm.stress_at(points)[last_full_reversal(cm.driver)]


def random_stress_history(n: int = 40, seed: int = 5, *, nu: float = 0.342) -> np.ndarray:
    """Random non-proportional histories of 11 steps at ``n`` points in plane strain
    (sigma_zz = nu (sxx + syy)): (11, n, 4) stresses in MPa."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2 * np.pi, 11)
    a, b = rng.normal(size=(n, 4)) * 100, rng.normal(size=(n, 4)) * 40
    s = a[None] * np.sin(t)[:, None, None] + b[None] * np.cos(2 * t)[:, None, None]
    s += rng.normal(size=(1, n, 4)) * 30
    s[..., 3] = nu * (s[..., 0] + s[..., 1])
    return s


def in_plane_scan(
    stress: np.ndarray,
    *,
    E: float,
    nu: float,
    step_deg: float,
    mean_stress=None,
    findley_k: float = 0.3,
    fatemi_socie_k: float = 0.5,
    yield_strength: float = 941.8,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Every criterion's largest value at each point of ``stress`` over the in-plane planes
    every ``step_deg`` degrees, in double, and the plane's angle (degrees): the brute force
    the searches are measured against."""
    criteria = cp._make_criteria(
        METHODS, E, nu, findley_k, fatemi_socie_k, yield_strength, mean_stress
    )
    theta = np.deg2rad(np.arange(0.0, 180.0, step_deg))[None]
    value = {c.name: np.empty(stress.shape[1]) for c in criteria}
    angle = {c.name: np.empty(stress.shape[1]) for c in criteria}
    for p in range(stress.shape[1]):
        q = cp._plane_stats(
            stress[:, p : p + 1], theta, np.full_like(theta, np.pi / 2), E, nu,
            shear=True, strains=True, in_plane=True,
        )  # fmt: skip
        for c in criteria:
            v = c.value(q, q["tau"] if c.needs_shear else 0 * q["tau"])[0]
            j = int(np.argmax(v))
            value[c.name][p], angle[c.name][p] = v[j], np.rad2deg(theta[0, j])
    return value, angle
