"""Where the stress cycle comes from: a small protocol and two implementations.

:class:`StressHistoryProvider` is what :func:`fretbem.fatigue.run_fatigue` consumes: stresses
at any points over the whole load history, optionally a driving load (for the default cycle)
and the surface quantities of the Ruiz parameters. :class:`CattaneoMindlinCycle` is the
closed-form half-plane reference (Hertz pressure, Cattaneo-Mindlin shear with Masing reversals
and the Nowell-Hills offset for an in-phase bulk stress); :class:`GridStressHistory`
interpolates stresses given on scattered points (e.g. exported from another code). A
simulation's stress evaluation plugs in by implementing the same three members.

Conventions (those of :mod:`fretbem.stress.closed_form`): points are [x, depth] in mm with
depth >= 0 below the surface y = 0; stress components [sxx, syy, sxy, szz] (MPa) are in the
global frame, y up, the body below the surface.
"""

from __future__ import annotations

import itertools
import math
from typing import Protocol, runtime_checkable

import attrs
import numpy as np

from fretbem.stress.closed_form import elliptical_pressure_stress, elliptical_shear_stress

from .cycle import turning_points
from .errors import FatigueInputError

__all__ = [
    "CattaneoMindlinCycle",
    "GridStressHistory",
    "StressHistoryProvider",
    "SurfaceHistory",
]


@attrs.frozen(eq=False)
class SurfaceHistory:
    """Surface quantities over the history at surface points ``x`` (S,), arrays (n_steps, S).

    ``slip`` is the relative tangential displacement of the two surfaces (mm), up to a
    constant per point; only its range over the cycle is used.
    """

    x: np.ndarray
    shear_traction: np.ndarray
    surface_stress_xx: np.ndarray
    slip: np.ndarray


@runtime_checkable
class StressHistoryProvider(Protocol):
    """What the fatigue evaluation needs from a stress source."""

    @property
    def n_steps(self) -> int:
        """Number of load steps in the history."""

    @property
    def driver(self) -> np.ndarray | None:
        """A load history (n_steps,) whose reversals define the default cycle, or None."""

    def stress_at(self, points: np.ndarray) -> np.ndarray:
        """Stress (n_steps, n, 4) at points (n, 2) = [x, depth]."""

    # optional members, used when present: ``contact_half_width`` (default map extent),
    # ``elastic_constants`` ((E, nu) of the stressed body, for the strains when the fatigue
    # material has none) and ``surface_history(x) -> SurfaceHistory`` (Ruiz parameters)


def _ellipse(x, centre, b):
    u = (np.asarray(x, dtype=float) - centre) / b
    return np.sqrt(np.clip(1.0 - u * u, 0.0, None))


def _slip_shape(x, centre, b):
    """|u| sqrt(u^2 - b^2) - b^2 ln((|u| + sqrt(u^2 - b^2)) / b) outside |u| < b, else 0."""
    u = np.abs(np.asarray(x, dtype=float) - centre)
    out = np.zeros_like(u)
    far = u > b
    r = np.sqrt(u[far] ** 2 - b * b)
    out[far] = u[far] * r - b * b * np.log((u[far] + r) / b)
    return out


@attrs.frozen(eq=False)
class CattaneoMindlinCycle:
    """Closed-form fretting cycle on a half-plane: 0 -> +Q -> -Q -> +Q with in-phase bulk stress.

    Attributes
    ----------
    a, p0, f : float
        Contact half-width (mm), peak Hertz pressure (MPa), friction coefficient.
    tangential_ratio : float
        Q_max / (f P), in (0, 1).
    sigma_bulk_max : float
        Bulk stress amplitude in phase with Q (MPa); 0 for pure Cattaneo-Mindlin.
    nu : float
        Poisson's ratio (sigma_zz in plane strain).
    plane_strain : bool
        Plane strain (sigma_zz = nu (sxx + syy)) or plane stress.
    steps_per_branch : int
        Load steps on each branch (loading, unloading, reloading).
    contact_modulus : float or None
        E* of the pair (E / (2 (1 - nu^2)) for identical bodies), MPa; needed only for slip.

    With these signs (those of :func:`fretbem.stress.closed_form.cattaneo_mindlin_stress`) the
    surface tension peaks at the edge x = -a at +Q (the trailing edge).
    """

    a: float
    p0: float
    f: float
    tangential_ratio: float
    sigma_bulk_max: float = 0.0
    nu: float = 0.3
    plane_strain: bool = True
    steps_per_branch: int = 6
    contact_modulus: float | None = None
    history: tuple[float, ...] | None = attrs.field(
        default=None, converter=lambda v: None if v is None else tuple(float(x) for x in v)
    )

    def __attrs_post_init__(self) -> None:
        if not (self.a > 0 and self.p0 > 0 and self.f > 0):
            raise FatigueInputError("a, p0 and f must be > 0")
        if not 0.0 < self.tangential_ratio < 1.0:
            raise FatigueInputError(
                f"Q_max / (f P) must lie in (0, 1) for partial slip, got {self.tangential_ratio}"
            )
        if self.steps_per_branch < 2:
            raise FatigueInputError("steps_per_branch must be >= 2")
        if self.history is not None:
            self._check_history()
        c = self.a * math.sqrt(1.0 - self.tangential_ratio)
        e = self.a * abs(self.sigma_bulk_max) / (4.0 * self.f * self.p0)
        if e + c > self.a * (1 + 1e-12):
            limit = 4.0 * self.f * self.p0 * (1.0 - math.sqrt(1.0 - self.tangential_ratio))
            raise FatigueInputError(
                f"bulk stress {self.sigma_bulk_max} MPa beyond the Nowell-Hills limit "
                f"{limit:.4g} MPa: the stick zone leaves the contact (use a numerical solution)"
            )

    @property
    def contact_half_width(self) -> float:
        """a, mm: sets the default extent of the parameter map."""
        return self.a

    def _check_history(self) -> None:
        h = np.asarray(self.history)
        if h.size < 2 or h[0] != 0.0 or np.max(np.abs(h)) > self.tangential_ratio * (1 + 1e-12):
            raise FatigueInputError(
                "history must start at Q = 0 and stay within |Q/(fP)| <= tangential_ratio"
            )
        turns = [0.0]
        for r in self._turning_values(h):
            turns.append(r)
        for k in range(2, len(turns)):
            previous = abs(turns[k - 1] - turns[k - 2]) * (2.0 if k == 2 else 1.0)
            if abs(turns[k] - turns[k - 1]) > previous * (1 + 1e-12):
                raise FatigueInputError(
                    "the closed form (Masing branches without memory erasure) needs each load "
                    "reversal to stay within the previous one"
                )

    @staticmethod
    def _turning_values(h: np.ndarray) -> list[float]:
        return [float(h[i]) for i in turning_points(h)[1:]]

    @property
    def tangential_history(self) -> np.ndarray:
        """Q / (f P) at every step: ``history``, or by default 0 -> +r -> -r -> +r."""
        if self.history is not None:
            return np.asarray(self.history)
        n = self.steps_per_branch
        r = self.tangential_ratio
        return np.concatenate(
            [
                np.linspace(0, r, n + 1),
                np.linspace(r, -r, 2 * n + 1)[1:],
                np.linspace(-r, r, 2 * n + 1)[1:],
            ]
        )

    @property
    def n_steps(self) -> int:
        """Number of load steps."""
        return self.tangential_history.size

    @property
    def driver(self) -> np.ndarray:
        """Q / (f P) history: the default cycle is its last full reversal."""
        return self.tangential_history

    def _increment(self, dr: float, scale: float):
        """Terms of a load increment dr (in Q/fP) from a turning point; Masing scale 1 or 2.

        The stick zone of an increment sits at e = a k |dr| / (4 scale f p0) whatever the
        direction of dr: negating every load negates the tractions and keeps the zones.
        """
        fp0, a = self.f * self.p0, self.a
        k = self.sigma_bulk_max / self.tangential_ratio  # sigma_B = k Q/(fP), in phase
        sign = 1.0 if dr >= 0 else -1.0
        c = a * math.sqrt(max(1.0 - abs(dr) / scale, 0.0))
        e = a * k * abs(dr) / (4 * scale * fp0)
        return [(sign * scale * fp0, a, 0.0), (-sign * scale * fp0 * c / a, c, e)]

    def _terms(self, step: int):
        """Shear terms (q0, half-width, centre) and the bulk stress at one step.

        First loading: Cattaneo-Mindlin with the Nowell-Hills offset; after each turning point
        the state there plus an increment of twice the scale (Masing), e.g. unloading from
        (Q_max, sigma_max): - 2 f p0 [E_a - (c'/a) E_c'(x - e')], c'/a = sqrt(1 - dQ/(2fP)),
        e' = a d(sigma)/(8 f p0) (Hills and Nowell 1994, ch. 5).
        """
        h = self.tangential_history
        k = self.sigma_bulk_max / self.tangential_ratio
        turns = [int(i) for i in turning_points(h[: step + 1])] if step > 0 else [0]
        # turning points strictly before this step, then the step itself
        marks = [t for t in turns if t < step] + [step]
        terms = self._increment(h[marks[1]] if len(marks) > 1 else 0.0, 1.0)
        for t0, t1 in itertools.pairwise(marks[1:]):
            terms = terms + self._increment(h[t1] - h[t0], 2.0)
        return terms, k * h[step]

    def stress_at(self, points: np.ndarray) -> np.ndarray:
        """Stress history (n_steps, n, 4) at points (n, 2) = [x, depth]."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        x, z = pts[:, 0], pts[:, 1]
        kw = {"nu": self.nu, "plane_strain": self.plane_strain}
        pressure = elliptical_pressure_stress(x, z, a=self.a, p0=self.p0, **kw)
        cache: dict = {}
        out = np.empty((self.n_steps, x.size, 4))
        for step in range(self.n_steps):
            terms, bulk = self._terms(step)
            total = pressure.copy()
            for q0, b, x0 in terms:
                if b <= 0.0 or q0 == 0.0:
                    continue
                key = (b, x0)
                if key not in cache:
                    cache[key] = elliptical_shear_stress(x, z, b=b, q0=1.0, centre=x0, **kw)
                total += q0 * cache[key]
            total[:, 0] += bulk
            if self.plane_strain:
                total[:, 3] += self.nu * bulk
            out[step] = total
        return out

    def surface_history(self, x: np.ndarray) -> SurfaceHistory:
        """Shear traction, surface sigma_xx and slip over the history at surface points x.

        Slip by superposing the Cattaneo-Mindlin slip of each stick-zone term (Masing);
        exact for sigma_bulk_max = 0; with a bulk stress the strain mismatch of the
        specimen is not in the slip, so the slip needs a numerical solution: refused.
        """
        x = np.asarray(x, dtype=float)
        if self.contact_modulus is None:
            raise FatigueInputError("slip needs the contact modulus E* (contact_modulus)")
        if self.sigma_bulk_max != 0.0:
            raise FatigueInputError(
                "the closed-form slip covers sigma_bulk_max = 0 only; use a simulation's slip"
            )
        q = np.zeros((self.n_steps, x.size))
        slip = np.zeros_like(q)
        for step in range(self.n_steps):
            terms, _ = self._terms(step)
            for q0, b, x0 in terms:
                if b <= 0.0:
                    continue
                q[step] += q0 * _ellipse(x, x0, b)
                if b < self.a:
                    slip[step] -= q0 / (b * self.contact_modulus) * _slip_shape(x, x0, b)
        sxx = self.stress_at(np.stack([x, np.zeros_like(x)], axis=1))[:, :, 0]
        return SurfaceHistory(x=x, shear_traction=q, surface_stress_xx=sxx, slip=slip)


@attrs.frozen(eq=False)
class GridStressHistory:
    """Stress history given at scattered points, linearly interpolated (Delaunay).

    Attributes
    ----------
    points : ndarray (n, 2)
        [x, depth] of the samples.
    stress : ndarray (n_steps, n, 4)
        Stress history at the samples.
    driver : ndarray (n_steps,) or None
        Load history for the default cycle.
    """

    points: np.ndarray = attrs.field(converter=lambda v: np.asarray(v, dtype=float))
    stress: np.ndarray = attrs.field(converter=lambda v: np.asarray(v, dtype=float))
    driver: np.ndarray | None = None
    _interp: object = attrs.field(init=False, repr=False, default=None)

    def __attrs_post_init__(self) -> None:
        if self.points.ndim != 2 or self.points.shape[1] != 2:
            raise FatigueInputError(f"points must have shape (n, 2), got {self.points.shape}")
        if self.stress.ndim != 3 or self.stress.shape[1:] != (self.points.shape[0], 4):
            raise FatigueInputError(
                f"stress must have shape (n_steps, {self.points.shape[0]}, 4), "
                f"got {self.stress.shape}"
            )
        from scipy.interpolate import LinearNDInterpolator

        values = self.stress.transpose(1, 0, 2).reshape(self.points.shape[0], -1)
        object.__setattr__(self, "_interp", LinearNDInterpolator(self.points, values))

    @property
    def n_steps(self) -> int:
        """Number of load steps."""
        return self.stress.shape[0]

    def stress_at(self, points: np.ndarray) -> np.ndarray:
        """Interpolated stress (n_steps, n, 4); points outside the samples' hull are refused."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        values = self._interp(pts)
        if not np.all(np.isfinite(values)):
            raise FatigueInputError("points outside the sampled region: extend the stress grid")
        return values.reshape(pts.shape[0], self.n_steps, 4).transpose(1, 0, 2)
