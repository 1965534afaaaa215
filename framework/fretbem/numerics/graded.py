"""Near-singular quadrature: a composite Gauss rule graded toward a nearby point.

Shared by the BEM assembly (collocation points near an element) and the stress evaluation
(interior points near the boundary): both integrate kernels that vary on the scale of the
distance to the point, so the pieces shrink geometrically toward it.
"""

from __future__ import annotations

import numpy as np

from .quadrature import QuadratureRule

__all__ = ["graded_rule"]


def graded_rule(
    centre: np.ndarray, distance_local: np.ndarray, n_points: int, ratio: float
) -> tuple[np.ndarray, np.ndarray]:
    """Composite Gauss rule on [-1, 1] graded geometrically toward ``centre`` on both sides.

    Sub-intervals shrink by ``ratio`` until they are about as small as the distance to the
    singularity (local units), so every piece sees it at >= its own length. Returns local
    coordinates and weights, each (len(centre), pieces * n_points).
    """
    base = QuadratureRule.gauss_legendre(n_points)
    local, weight = [], []
    for side in (-1.0, 1.0):
        length = np.where(side < 0, centre + 1.0, 1.0 - centre)
        need = np.log(np.maximum(distance_local, 1e-14) / np.maximum(length, 1e-300))
        levels = np.clip(np.ceil(need / np.log(ratio)) + 1, 1, 60).astype(int)
        top = int(levels.max())
        k = np.minimum(np.arange(top + 1)[None, :], levels[:, None])
        edges = length[:, None] * ratio**k  # decreasing distances from the centre
        edges = np.concatenate([edges, np.zeros((len(centre), 1))], axis=1)
        t, w = base.mapped(edges[:, 1:], edges[:, :-1])  # (P, pieces, n)
        local.append((centre[:, None, None] + side * t).reshape(len(centre), -1))
        weight.append(w.reshape(len(centre), -1))
    return np.concatenate(local, axis=1), np.concatenate(weight, axis=1)
