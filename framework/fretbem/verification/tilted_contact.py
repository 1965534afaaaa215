"""An incomplete half-plane contact of any profile, tilted: pressure and shear by quadrature.

An independent reference for the pad block's rotation (:mod:`fretbem.contact.rotation`):
two elastically similar half-planes touch where the relative profile g(x) = f(x) + theta x
(f the pad's profile above its lowest point, theta its tilt, counterclockwise) closes, over
(e1, e2), with a pressure bounded at both edges. Half-plane theory (D.A. Hills, D. Nowell
and A. Sackfield, *Mechanics of Elastic Contacts*, 1993, ch. 5; J.R. Barber, *Contact
Mechanics*, 2018, ch. 8) gives

    (1/pi) PV int p(s) / (x - s) ds = (E*/2) g'(x),
    p(x) = (E* / (2 pi)) w(x) int (g'(s) - g'(x)) / ((s - x) w(s)) ds,  w = sqrt((x-e1)(e2-x)),

with the edges fixed by the consistency condition int g'(s) / w(s) ds = 0 and the load
P = (E*/2) int (s - c) g'(s) / w(s) ds (c the middle of the contact). The integrals are
Gauss-Chebyshev sums, not fretbem's discretisation. The partial-slip shear under a
tangential load Q at fixed P and tilt is the Ciavarella-Jager superposition
q = f [p(x; P) - p(x; P - abs(Q) / f)], the corrective over the stick zone of the same tilted
profile. Units mm, N/mm, MPa; p >= 0; q the shear the pad exerts on the specimen in +x.
"""

from __future__ import annotations

from collections.abc import Callable

import attrs
import numpy as np
import scipy.optimize

from fretbem.validators import positive_field

#: Gauss-Chebyshev points of the integrals (the profile's kinks converge slowly: at 4000
#: points the rounded flat's pressure moves by < 1e-5 of its peak against 8000)
POINTS = 4000


@attrs.frozen
class TiltedContact:
    """Two similar half-planes touching along a tilted profile.

    Attributes
    ----------
    slope : callable
        f'(x), the slope of the pad's profile (vectorised).
    effective_modulus : float
        E* of the pair.
    friction : float
    """

    slope: Callable[[np.ndarray], np.ndarray]
    effective_modulus: float = attrs.field(
        converter=positive_field("the contact modulus E*, MPa", "give E* from effective_modulus()")
    )
    friction: float = attrs.field(
        default=0.3, converter=positive_field("the Coulomb coefficient f", "give f > 0 (e.g. 0.3)")
    )

    def _gap_slope(self, x, tilt: float) -> np.ndarray:
        return self.slope(np.asarray(x, float)) + tilt

    def _nodes(self, e1: float, e2: float) -> tuple[np.ndarray, float]:
        """Gauss-Chebyshev points of the first kind over (e1, e2) and their weight."""
        j = np.arange(1, POINTS + 1)
        s = np.cos((2 * j - 1) * np.pi / (2 * POINTS))
        return 0.5 * (e1 + e2) + 0.5 * (e2 - e1) * s, np.pi / POINTS

    def conditions(self, e1: float, e2: float, tilt: float) -> tuple[float, float]:
        """The consistency integral and the load P of the edges (e1, e2)."""
        s, weight = self._nodes(e1, e2)
        slope = self._gap_slope(s, tilt)
        centre = 0.5 * (e1 + e2)
        return weight * slope.sum(), 0.5 * self.effective_modulus * weight * (
            (s - centre) * slope
        ).sum()

    def edges(self, load: float, tilt: float, guess: tuple[float, float]) -> tuple[float, float]:
        """The contact edges (e1, e2) under P = ``load`` at ``tilt`` (from ``guess``)."""

        def residual(v):
            consistency, total = self.conditions(v[0], v[1], tilt)
            span = max(v[1] - v[0], 1e-12)
            return [consistency * span, total / load - 1.0]

        solution = scipy.optimize.fsolve(residual, guess, xtol=1e-13, full_output=True)
        e1, e2 = solution[0]
        if solution[2] != 1 or not e2 > e1:
            raise ValueError(f"no contact edges found for P = {load}, tilt = {tilt}")
        return float(e1), float(e2)

    def pressure(self, x, load: float, tilt: float, guess) -> np.ndarray:
        """p(x) under P and the tilt (0 outside the contact)."""
        e1, e2 = self.edges(load, tilt, guess)
        x = np.asarray(x, float)
        s, weight = self._nodes(e1, e2)
        inside = np.flatnonzero((x > e1) & (x < e2))
        out = np.zeros_like(x)
        slope = self._gap_slope(s, tilt)
        for chunk in np.array_split(inside, max(1, inside.size // 256)):  # bounded memory
            xi = x[chunk][:, None]
            ds = s[None, :] - xi
            ds = np.where(np.abs(ds) < 1e-14, 1e-14, ds)
            integral = ((slope[None, :] - self._gap_slope(xi, tilt)) / ds).sum(axis=1)
            w = np.sqrt((x[chunk] - e1) * (e2 - x[chunk]))
            out[chunk] = self.effective_modulus / (2 * np.pi) * w * weight * integral
        return out

    def shear(self, x, load: float, tangential: float, tilt: float, guess) -> np.ndarray:
        """q(x) at Q = ``tangential`` reached monotonically at fixed P and tilt."""
        full = self.pressure(x, load, tilt, guess)
        reduced = load - abs(tangential) / self.friction
        corrective = self.pressure(x, reduced, tilt, guess) if reduced > 0 else 0.0
        return np.sign(tangential) * self.friction * (full - corrective)

    def moment(self, load: float, tilt: float, guess) -> float:
        """M = -int x p dx: the moment a block applies to the pad about x = 0."""
        e1, e2 = self.edges(load, tilt, guess)
        x = np.linspace(e1, e2, 2001)  # the trapezoid rule's error: ~1e-5 of M
        return float(-np.trapezoid(x * self.pressure(x, load, tilt, (e1, e2)), x))
