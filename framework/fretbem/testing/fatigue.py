"""Stress histories for testing critical-plane searches.

Seeded, so a test sees the same history on every run: a fretting contact's cycle at random
points below it, and random non-proportional histories in plane strain.
"""

from __future__ import annotations

import numpy as np

from fretbem.fatigue import CattaneoMindlinCycle, last_full_reversal

__all__ = ["contact_stress_history", "random_stress_history"]


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
