"""The rounded-flat punch on a half-plane: pressure, load and partial-slip shear in closed form.

A flat of half-width b with circular fillets of radius R, pressed on an elastically similar
half-plane (Dundurs beta = 0), touches over |x| < a with a pressure bounded at both ends
(Ciavarella, Hills and Monno, "The influence of rounded edges on indentation by a flat
punch", Proc. IMechE C 212 (1998) 319-328). With sin(phi0) = b/a,

    P(a) = (E*/R) [a^2 ((pi/2 - phi0)/2 + sin(2 phi0)/4) - a b cos(phi0)],

and the pressure is :meth:`RoundedFlatPunch.pressure`. Under a tangential load Q the shear is
the superposition of Ciavarella (1998) and Jager (1998),

    q(x) = f [p(x; a) - p(x; c)],  P(c) = P - |Q|/f,

a corrective of the same profile over the stick zone |x| < c; a load reversal by a swing dQ
adds -2 f [p(x; a) - p(x; c')] with P(c') = P - |dQ|/(2 f) (Masing's rule). Conventions as
:mod:`fretbem.verification.closed_forms`: p >= 0, q the shear the pad exerts on the specimen
in +x, units mm, N/mm, MPa.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from numpy.typing import ArrayLike

from fretbem.validators import positive_field

__all__ = ["RoundedFlatPunch"]


@attrs.frozen
class RoundedFlatPunch:
    """Closed-form half-plane contact of a rounded flat (Ciavarella, Hills and Monno 1998).

    Attributes
    ----------
    flat : float
        Half-width b of the flat, mm.
    edge_radius : float
        Radius R of the fillets, mm.
    effective_modulus : float
        Contact modulus E* (:func:`~fretbem.verification.closed_forms.effective_modulus`).
    friction : float
        Coulomb coefficient f (used by the shear only).
    """

    flat: float = attrs.field(
        converter=positive_field("the flat's half-width b, mm", "give b in mm")
    )
    edge_radius: float = attrs.field(
        converter=positive_field("the fillets' radius R, mm", "give R in mm")
    )
    effective_modulus: float = attrs.field(
        converter=positive_field("the contact modulus E*, MPa", "give E* from effective_modulus()")
    )
    friction: float = attrs.field(
        default=0.3, converter=positive_field("the Coulomb coefficient f", "give f > 0 (e.g. 0.3)")
    )

    def load(self, half_width: float) -> float:
        """Normal load P(a) per unit thickness at contact half-width a >= b (0 at a = b)."""
        a, b = float(half_width), self.flat
        if a <= b:
            return 0.0
        phi = math.asin(b / a)
        bracket = a * a * ((math.pi / 2 - phi) / 2 + math.sin(2 * phi) / 4)
        return self.effective_modulus / self.edge_radius * (bracket - a * b * math.cos(phi))

    def half_width(self, load: float) -> float:
        """Contact half-width a with P(a) = load (b at zero load)."""
        from scipy.optimize import brentq

        if load <= 0.0:
            return self.flat
        upper = self.flat + math.sqrt(8.0 * load * self.edge_radius / self.effective_modulus)
        while self.load(upper) < load:
            upper *= 2.0
        return brentq(lambda a: self.load(a) - load, self.flat, upper, xtol=1e-14, rtol=1e-14)

    def pressure(self, x: ArrayLike, half_width: float) -> np.ndarray:
        """Pressure p(x) for contact half-width a (zero outside |x| < a)."""
        x = np.asarray(x, dtype=float)
        a, b = float(half_width), self.flat
        out = np.zeros_like(x)
        if a <= b:
            return out
        inside = np.abs(x) < a
        xi = x[inside]
        root = np.sqrt(a * a - xi * xi)

        def log_term(s: float) -> np.ndarray:
            with np.errstate(divide="ignore"):
                return np.log(np.abs((a * a - xi * s + root * math.sqrt(a * a - s * s)) / (s - xi)))

        phi = math.asin(b / a)
        value = (math.pi - 2 * phi) * root
        # (x -+ b) log|...| -> 0 where x = +-b: the terms vanish there
        with np.errstate(invalid="ignore"):
            right = (xi - b) * (log_term(b) - math.log(a))
            left = (xi + b) * (math.log(a) - log_term(-b))
        value += np.where(np.isfinite(right), right, 0.0) + np.where(np.isfinite(left), left, 0.0)
        out[inside] = self.effective_modulus / (2 * math.pi * self.edge_radius) * value
        return out

    def stick_half_width(self, load: float, tangential: float) -> float:
        """Stick-zone half-width c at first loading to Q: P(c) = P - |Q|/f (b if that is < 0)."""
        slip = abs(tangential) / self.friction
        if slip >= load:
            raise ValueError(
                f"|Q| = {abs(tangential):g} >= f P = {self.friction * load:g}: gross sliding"
            )
        return self.half_width(load - slip)

    def shear(self, x: ArrayLike, load: float, tangential: float) -> np.ndarray:
        """Shear q(x) after first loading from 0 to Q at constant P (sign of Q)."""
        a = self.half_width(load)
        c = self.stick_half_width(load, tangential)
        sign = math.copysign(1.0, tangential) if tangential else 0.0
        return sign * self.friction * (self.pressure(x, a) - self.pressure(x, c))

    def shear_after_reversal(
        self, x: ArrayLike, load: float, peak: float, tangential: float
    ) -> np.ndarray:
        """Shear after loading 0 -> ``peak`` then back to ``tangential`` (Masing's rule)."""
        a = self.half_width(load)
        swing = tangential - peak
        if abs(swing) >= 2 * self.friction * load:
            raise ValueError("the reversal swing exceeds 2 f P: gross sliding")
        c = self.half_width(load - abs(swing) / (2 * self.friction))
        back = math.copysign(1.0, swing) if swing else 0.0
        corrective = 2 * back * self.friction * (self.pressure(x, a) - self.pressure(x, c))
        return self.shear(x, load, peak) + corrective
