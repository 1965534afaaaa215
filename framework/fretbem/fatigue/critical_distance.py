"""Theory of critical distances: the parameter at or averaged near the hot spot, over length L.

L = (1/pi) (Delta K_th / Delta sigma_0)^2 (El Haddad, Topper and Smith 1979; Taylor, The Theory
of Critical Distances, Elsevier 2007), with Delta K_th the threshold stress-intensity range and
Delta sigma_0 the plain fatigue limit as a range (fully reversed). Point method: the value at
L/2 from the hot spot along the chosen direction; line method: the mean over a line of length
2L; area method: the mean over a half disc of radius ``area_radius_factor * L`` (Taylor's 1.32
by default) centred at the hot spot and facing into the body. The parameter is reached through
a callable ``parameter_at(points) -> values`` (points (n, 2) as [x, depth]), so a closed-form
field, an interpolated grid or a simulation's stress evaluation can all be used.
"""

from __future__ import annotations

from collections.abc import Callable

import attrs
import numpy as np

from fretbem.validators import real_number

from .errors import FatigueInputError

__all__ = [
    "AREA_RADIUS_FACTOR",
    "CriticalDistanceValues",
    "critical_distance_from_threshold",
    "critical_distance_values",
]

#: Taylor's area-method radius in units of L (semicircle of radius 1.32 L)
AREA_RADIUS_FACTOR = 1.32

ParameterAt = Callable[[np.ndarray], np.ndarray]


def critical_distance_from_threshold(
    threshold_sif_range: float, fatigue_limit_range: float
) -> float:
    """L in mm from Delta K_th (MPa sqrt(m)) and the plain fatigue limit RANGE (MPa)."""
    threshold_sif_range, fatigue_limit_range = (
        real_number(name, value, what=unit, fix=f"give {name} > 0", error=FatigueInputError)
        for name, value, unit in (
            ("threshold_sif_range", threshold_sif_range, "Delta K_th, MPa sqrt(m)"),
            ("fatigue_limit_range", fatigue_limit_range, "Delta sigma_0, MPa"),
        )
    )
    if not (threshold_sif_range > 0 and fatigue_limit_range > 0):
        raise FatigueInputError(
            "the critical distance needs Delta K_th > 0 (MPa sqrt(m)) and Delta sigma_0 > 0 (MPa), "
            f"got {threshold_sif_range}, {fatigue_limit_range}"
        )
    return 1000.0 / np.pi * (threshold_sif_range / fatigue_limit_range) ** 2


@attrs.frozen
class CriticalDistanceValues:
    """Parameter values of the three critical-distance methods for one hot spot.

    Attributes
    ----------
    critical_distance : float
        L in mm.
    point_value, line_value, area_value : float
        Value at L/2, mean over 2L, mean over the half disc of radius ``area_radius``.
    point : tuple[float, float]
        The point-method location [x, depth].
    area_radius : float
        Radius of the area-method half disc, mm.
    """

    critical_distance: float
    point_value: float
    line_value: float
    area_value: float
    point: tuple[float, float]
    area_radius: float


def _direction(direction) -> np.ndarray:
    d = np.asarray(direction, dtype=float)
    if d.shape != (2,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
        raise FatigueInputError(
            f"the critical direction must be a non-zero 2-vector, got {direction!r}"
        )
    d = d / np.linalg.norm(d)
    if d[1] < 0:
        raise FatigueInputError(
            "the critical direction must point into the body (depth component >= 0)"
        )
    return d


def critical_distance_values(
    parameter_at: ParameterAt,
    hot_spot,
    critical_distance: float,
    *,
    direction=(0.0, 1.0),
    area_radius_factor: float = AREA_RADIUS_FACTOR,
    line_nodes: int = 24,
    radial_nodes: int = 12,
    angular_nodes: int = 24,
) -> CriticalDistanceValues:
    """Point, line and area method values around ``hot_spot`` ([x, depth], mm).

    ``direction`` ([x, depth], into the body) is the critical direction: straight down by
    default, or e.g. along the critical plane's trace.
    """
    critical_distance = real_number(
        "critical_distance", critical_distance, what="L, mm", fix="give L > 0 in mm",
        error=FatigueInputError,
    )  # fmt: skip
    if not critical_distance > 0:
        raise FatigueInputError(f"the critical distance L must be > 0 mm, got {critical_distance}")
    h = np.asarray(hot_spot, dtype=float)
    d = _direction(direction)
    L = float(critical_distance)
    point = h + 0.5 * L * d
    # line method: Gauss-Legendre over s in [0, 2L]
    s, w = np.polynomial.legendre.leggauss(line_nodes)
    s = L * (s + 1.0)
    line_pts = h + s[:, None] * d
    # area method: half disc of radius R facing d; polar Gauss (r dr) x Gauss in angle
    R = area_radius_factor * L
    r, wr = np.polynomial.legendre.leggauss(radial_nodes)
    r, wr = 0.5 * R * (r + 1.0), 0.5 * R * wr
    phi, wphi = np.polynomial.legendre.leggauss(angular_nodes)
    phi, wphi = 0.5 * np.pi * phi, 0.5 * np.pi * wphi
    t = np.array([d[1], -d[0]])  # tangent, so that phi = +-pi/2 lies along the surface
    rr, pp = np.meshgrid(r, phi, indexing="ij")
    area_pts = h + (rr * np.cos(pp))[..., None] * d + (rr * np.sin(pp))[..., None] * t
    area_pts = area_pts.reshape(-1, 2)
    area_pts[:, 1] = np.maximum(area_pts[:, 1], h[1])  # round-off: stay inside the body
    values = np.asarray(
        parameter_at(np.vstack([point[None], line_pts, area_pts])), dtype=float
    ).ravel()
    if values.size != 1 + line_pts.shape[0] + area_pts.shape[0]:
        raise FatigueInputError("parameter_at must return one value per point")
    v_point = values[0]
    v_line = values[1 : 1 + line_nodes]
    v_area = values[1 + line_nodes :].reshape(radial_nodes, angular_nodes)
    line_mean = float(np.sum(w * v_line) / 2.0)
    area_mean = float(
        np.sum(wr[:, None] * r[:, None] * wphi[None] * v_area) / (0.5 * np.pi * R * R)
    )
    return CriticalDistanceValues(
        critical_distance=L,
        point_value=float(v_point),
        line_value=line_mean,
        area_value=area_mean,
        point=(float(point[0]), float(point[1])),
        area_radius=float(R),
    )
