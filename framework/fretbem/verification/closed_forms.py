"""Half-plane analytical solutions for 2D (line) contact: Hertz and Mindlin–Deresiewicz.

These are the references the BEM results are checked against (Johnson 1985, ch. 4 and 7;
Hills & Nowell 1994). Units are whatever the caller uses consistently (the project uses
mm, N, MPa); loads are per unit thickness.

Conventions (as in the reference scene, docs/theory.md): ``p >= 0`` is the contact pressure and
``q`` is the shear traction the upper body exerts on the lower body, in ``+x``, so that
``∫p dx = P`` and ``∫q dx = Q``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import attrs
import numpy as np
from numpy.typing import ArrayLike

from fretbem.validators import check_poisson, check_positive, positive_field

__all__ = [
    "HertzLineContact",
    "MindlinDeresiewicz",
    "dundurs_beta",
    "effective_modulus",
]


# --------------------------------------------------------------------------- validation


# --------------------------------------------------------------------------- elastic constants


def effective_modulus(
    E1: float, nu1: float, E2: float, nu2: float, *, plane_stress: bool = False
) -> float:
    """Contact modulus E* of two bodies: 1/E* = (1-nu1²)/E1 + (1-nu2²)/E2 (plane strain).

    In plane stress 1/E* = 1/E1 + 1/E2. For similar bodies in plane strain E* = E/(2(1-nu²)).
    """
    E1, E2 = check_positive("E1", E1), check_positive("E2", E2)
    nu1, nu2 = check_poisson("nu1", nu1), check_poisson("nu2", nu2)
    if plane_stress:
        return 1.0 / (1.0 / E1 + 1.0 / E2)
    return 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)


def dundurs_beta(
    E1: float, nu1: float, E2: float, nu2: float, *, plane_stress: bool = False
) -> float:
    """Dundurs' second parameter β of body 1 against body 2; normal and shear uncouple if β = 0.

    β = [(κ1-1)/μ1 - (κ2-1)/μ2] / [(κ1+1)/μ1 + (κ2+1)/μ2] with κ = 3-4ν (plane strain) or
    (3-ν)/(1+ν) (plane stress); swapping the bodies flips its sign.
    """
    E1, E2 = check_positive("E1", E1), check_positive("E2", E2)
    nu1, nu2 = check_poisson("nu1", nu1), check_poisson("nu2", nu2)

    def kappa(nu: float) -> float:
        return (3.0 - nu) / (1.0 + nu) if plane_stress else 3.0 - 4.0 * nu

    mu1, mu2 = E1 / (2.0 * (1.0 + nu1)), E2 / (2.0 * (1.0 + nu2))
    k1, k2 = kappa(nu1), kappa(nu2)
    return ((k1 - 1.0) / mu1 - (k2 - 1.0) / mu2) / ((k1 + 1.0) / mu1 + (k2 + 1.0) / mu2)


# --------------------------------------------------------------------------- Hertz


def _ellipse(x: np.ndarray, c: float) -> np.ndarray:
    """s_c(x) = sqrt(1 - x²/c²) for |x| < c, 0 elsewhere (and everywhere if c <= 0)."""
    if c <= 0.0:
        return np.zeros_like(x)
    return np.sqrt(np.maximum(1.0 - (x / c) ** 2, 0.0))  # np.clip's number, without its frames


@attrs.frozen
class HertzLineContact:
    """Hertzian line contact of two cylinders (or a cylinder on a flat), plane problem.

    Attributes
    ----------
    load : float
        Normal load per unit thickness P (> 0).
    effective_radius : float
        R_eff with 1/R_eff = 1/R1 + 1/R2 (R2 = inf for a flat).
    effective_modulus : float
        Contact modulus E*, see :func:`effective_modulus`.
    """

    load: float = attrs.field(
        converter=positive_field("the normal load P, N/mm", "give P > 0 in N/mm")
    )
    effective_radius: float = attrs.field(
        converter=positive_field("R_eff, mm", "give 1 / (1/R1 + 1/R2) in mm")
    )
    effective_modulus: float = attrs.field(
        converter=positive_field("the contact modulus E*, MPa", "give E* from effective_modulus()")
    )

    @classmethod
    def from_bodies(
        cls,
        *,
        load: float,
        radius_upper: float,
        radius_lower: float,
        E_upper: float,
        nu_upper: float,
        E_lower: float,
        nu_lower: float,
        plane_stress: bool = False,
    ) -> HertzLineContact:
        """Build from the two bodies' radii and elastic constants (``math.inf`` for a flat)."""
        curvature = 0.0
        for name, radius in (("radius_upper", radius_upper), ("radius_lower", radius_lower)):
            radius = float(radius)
            if not (radius > 0.0) or math.isnan(radius):
                raise ValueError(f"{name} must be > 0 (math.inf for a flat), got {radius!r}")
            curvature += 1.0 / radius
        if curvature == 0.0:
            raise ValueError("radius_upper and radius_lower are both infinite: no Hertz contact")
        modulus = effective_modulus(E_upper, nu_upper, E_lower, nu_lower, plane_stress=plane_stress)
        return cls(load=load, effective_radius=1.0 / curvature, effective_modulus=modulus)

    @property
    def half_width(self) -> float:
        """Contact half-width a = sqrt(4 P R_eff / (π E*))."""
        ratio = self.load * self.effective_radius / self.effective_modulus
        return math.sqrt(4.0 * ratio / math.pi)

    @property
    def peak_pressure(self) -> float:
        """Peak pressure p0 = 2P / (π a)."""
        return 2.0 * self.load / (math.pi * self.half_width)

    def pressure(self, x: ArrayLike) -> np.ndarray:
        """Contact pressure p(x) = p0 sqrt(1 - x²/a²) inside |x| < a, 0 outside."""
        x = np.asarray(x, dtype=float)
        return self.peak_pressure * _ellipse(x, self.half_width)


# --------------------------------------------------------------------------- Mindlin–Deresiewicz


@attrs.frozen
class MindlinDeresiewicz:
    """Partial slip under constant P and a varying tangential load Q (Cattaneo–Mindlin, Masing).

    Valid for elastically similar bodies (Dundurs β = 0), where the shear does not change p.
    A load path is the piecewise-linear sequence 0 -> history[0] -> ... -> history[-1]. Each
    load reversal at a turning point T adds 2 f p0 sign(Q - T) [s_a - (c/a) s_c] with
    c/a = sqrt(1 - |Q - T|/(2 f P)); passing an earlier turning point wipes out the reversals
    it closes (Masing's memory rule), and passing -T1 returns to the first-loading curve.

    Attributes
    ----------
    hertz : HertzLineContact
        The normal contact (P, a, p0), unchanged by the tangential load.
    friction : float
        Coulomb friction coefficient f (> 0).
    """

    hertz: HertzLineContact = attrs.field(validator=attrs.validators.instance_of(HertzLineContact))
    friction: float = attrs.field(
        converter=positive_field("the Coulomb coefficient f", "give f > 0 (e.g. 0.3 to 1.5)")
    )

    @property
    def sliding_limit(self) -> float:
        """Gross-sliding load f P; partial slip requires |Q| < f P on the whole path."""
        return self.friction * self.hertz.load

    def _stick_ratio(self, delta: float, scale: float) -> float:
        """c/a = sqrt(1 - |ΔQ| / (scale f P)) of a branch (scale 1: first loading, 2: reversal)."""
        return math.sqrt(max(1.0 - abs(delta) / (scale * self.sliding_limit), 0.0))

    def _states(self, history: ArrayLike) -> Iterator[tuple[float, ...]]:
        """Yield, after each value of the path, the active points (0, T1, ..., Tn, Q)."""
        values = np.atleast_1d(np.asarray(history, dtype=float))
        if values.ndim != 1:
            raise ValueError(f"history must be a 1-D sequence of loads, got shape {values.shape}")
        if not np.all(np.isfinite(values)):
            raise ValueError(f"history must contain finite loads only, got {values.tolist()!r}")
        limit = self.sliding_limit
        for i, value in enumerate(values):
            if abs(value) >= limit:
                raise ValueError(
                    f"history[{i}] is in gross sliding: |Q| = {abs(value):g} >= f P = {limit:g}; "
                    "no partial-slip solution exists (the whole contact slips)"
                )
        turning: list[float] = []  # active turning points T1..Tn
        current, direction = 0.0, 0.0
        for target in values:
            target = float(target)
            step = math.copysign(1.0, target - current) if target != current else 0.0
            if step != 0.0:
                if direction != 0.0 and step != direction:
                    turning.append(current)  # load reversal at ``current``
                direction = step
                # Memory rule: drop the reversals whose loops the new value closes.
                while turning:
                    if len(turning) == 1:
                        closed = (target - (-turning[0])) * step >= 0.0
                        drop = 1
                    else:
                        closed = (target - turning[-2]) * step >= 0.0
                        drop = 2
                    if not closed:
                        break
                    del turning[-drop:]
                current = target
            yield (0.0, *turning, current)

    def _traction(self, x: np.ndarray, points: tuple[float, ...]) -> np.ndarray:
        """q(x) for the active points (0, T1, ..., Tn, Q): first-loading term plus reversals."""
        a, p0 = self.hertz.half_width, self.hertz.peak_pressure
        s_a = _ellipse(x, a)
        q = np.zeros_like(x)
        for k in range(len(points) - 1):
            delta = points[k + 1] - points[k]
            if delta == 0.0:
                continue
            scale = 1.0 if k == 0 else 2.0  # the first loading spans f P, reversals 2 f P
            ratio = self._stick_ratio(delta, scale)  # c / a
            q += scale * math.copysign(1.0, delta) * (s_a - ratio * _ellipse(x, ratio * a))
        return self.friction * p0 * q

    def _final(self, history: ArrayLike) -> tuple[float, ...]:
        """Active points at the end of the path (Q = 0 state for an empty path)."""
        states = list(self._states(history))
        return states[-1] if states else (0.0, 0.0)

    def shear_traction(self, x: ArrayLike, history: ArrayLike) -> np.ndarray:
        """Shear traction q(x) at the end of the load path 0 -> history[0] -> ... -> history[-1]."""
        x = np.asarray(x, dtype=float)
        return self._traction(x, self._final(history))

    def shear_history(self, x: ArrayLike, history: ArrayLike) -> np.ndarray:
        """Shear traction after each value of the path, shape ``(len(history),) + x.shape``."""
        x = np.asarray(x, dtype=float)
        rows = [self._traction(x, state) for state in self._states(history)]
        return np.stack(rows) if rows else np.empty((0, *x.shape))

    def stick_zone(self, history: ArrayLike) -> tuple[float, float]:
        """Current stick zone (-c, c): c of the last active branch, the innermost stick zone."""
        points = self._final(history)
        delta = points[-1] - points[-2]
        scale = 1.0 if len(points) == 2 else 2.0
        c = self.hertz.half_width * self._stick_ratio(delta, scale)
        return (-c, c)


#: a path value within this fraction of f P counts as gross sliding in :class:`SlidingPath`
SLIDING_MARGIN = 1e-12


@attrs.frozen
class SlidingPath:
    """Mindlin-Deresiewicz read along a path that may reach gross sliding (|Q| = f P).

    Under displacement control Q stops at +-f P while the bodies slide. There the closed
    form's stick zone has shrunk to a point (c = 0, q = +-f p) and sliding on erases the
    memory of earlier reversals, which is what the Masing rules give for a path clamped
    to just inside +-f P; so each value is clamped to (1 - 1e-12) f P.

    Attributes
    ----------
    closed_form : MindlinDeresiewicz
    """

    closed_form: MindlinDeresiewicz

    #: this reference accepts paths that reach f P
    slides = True

    @property
    def hertz(self) -> HertzLineContact:
        """The normal contact."""
        return self.closed_form.hertz

    @property
    def friction(self) -> float:
        """Coulomb coefficient f."""
        return self.closed_form.friction

    def _clamped(self, history: ArrayLike) -> np.ndarray:
        limit = self.closed_form.sliding_limit * (1.0 - SLIDING_MARGIN)
        return np.clip(np.atleast_1d(np.asarray(history, dtype=float)), -limit, limit)

    def shear_traction(self, x: ArrayLike, history: ArrayLike) -> np.ndarray:
        """q(x) at the end of the (clamped) path."""
        return self.closed_form.shear_traction(x, self._clamped(history))

    def shear_history(self, x: ArrayLike, history: ArrayLike) -> np.ndarray:
        """q(x) after each value of the (clamped) path."""
        return self.closed_form.shear_history(x, self._clamped(history))

    def stick_zone(self, history: ArrayLike) -> tuple[float, float]:
        """Current stick zone (-c, c) of the (clamped) path."""
        return self.closed_form.stick_zone(self._clamped(history))
