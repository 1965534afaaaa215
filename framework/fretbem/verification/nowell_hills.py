"""Partial slip with a bulk stress in the specimen: the Nowell-Hills solution (half-plane).

A cylindrical pad under constant P and a tangential load Q, on a specimen carrying a bulk
stress sigma_B in phase with Q (sigma_B = k Q along the whole path). The stick zone keeps
the Cattaneo-Mindlin width c but moves by e = a sigma_B / (4 f p0); every load reversal
adds a reverse-slip branch of twice the scale, shifted by the change of sigma_B over
(8 f p0) (Masing's rule). Nowell and Hills, "Mechanics of fretting fatigue tests", Int. J.
Mech. Sci. 29 (1987) 355-365; Hills and Nowell, Mechanics of Fretting Fatigue (1994), ch. 5.

The closed form holds while each stick zone stays inside the contact, |e| + c <= a; past
that one edge reverses slip and only a numerical solution exists (:meth:`NowellHills.limit`).
Conventions as :mod:`fretbem.verification.closed_forms`:
q is the shear the pad exerts on the specimen,
in +x; sigma_B > 0 is tension along x.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from numpy.typing import ArrayLike

from fretbem.errors import InputError
from fretbem.validators import number_field, positive_field

from .closed_forms import HertzLineContact, MindlinDeresiewicz, _ellipse

__all__ = ["NotApplicableError", "NowellHills"]

#: relative tolerance on the ratio sigma_B / Q along a path (in-phase loading)
PHASE_TOLERANCE = 1e-9


class NotApplicableError(InputError):
    """The closed form does not apply to this load path (the message says why)."""


@attrs.frozen
class NowellHills:
    """Shear traction, stick zone and validity of the Nowell-Hills solution.

    Attributes
    ----------
    hertz : HertzLineContact
        The normal contact (P, a, p0), unchanged by Q and sigma_B (similar bodies).
    friction : float
        Coulomb coefficient f.
    shift : float
        +1 or -1: direction of the stick-zone offset for sigma_B and Q of the same sign, in
        the caller's axes (+1: toward +x). Fretbem's rig puts the pad's Q and the pull at the
        specimen's +x end so that both move the specimen surface the same way; its tests
        fix the sign against the numerical solution.
    """

    hertz: HertzLineContact = attrs.field(validator=attrs.validators.instance_of(HertzLineContact))
    friction: float = attrs.field(
        converter=positive_field("the Coulomb coefficient f", "give f > 0 (e.g. 0.3 to 1.5)")
    )
    shift: float = attrs.field(
        default=1.0,
        converter=number_field("the stick zone's offset direction", "give +1 or -1"),
    )

    def __attrs_post_init__(self) -> None:
        if not (self.friction > 0 and math.isfinite(self.friction)):
            raise ValueError(f"friction must be a finite number > 0, got {self.friction!r}")
        if self.shift not in (1.0, -1.0):
            raise ValueError(f"shift must be +1 or -1, got {self.shift!r}")

    @property
    def _md(self) -> MindlinDeresiewicz:
        return MindlinDeresiewicz(self.hertz, self.friction)

    def ratio(self, tangential: ArrayLike, bulk: ArrayLike) -> float:
        """k in sigma_B = k Q along the path; NotApplicableError if the path is not in phase."""
        q = np.atleast_1d(np.asarray(tangential, float))
        s = np.atleast_1d(np.asarray(bulk, float))
        if q.shape != s.shape:
            raise ValueError(
                f"the Q path has {q.size} values but the bulk path {s.size}; give one bulk "
                "stress per value of Q"
            )
        loaded = np.abs(q) > 0
        scale = max(np.max(np.abs(s), initial=0.0), 1e-300)
        if np.any(np.abs(s[~loaded]) > PHASE_TOLERANCE * scale):
            raise NotApplicableError(
                "the bulk stress is not zero where Q is zero (a mean bulk stress): the "
                "Nowell-Hills closed form needs sigma_B in phase with Q (sigma_B = k Q)"
            )
        if not loaded.any():
            return 0.0
        k = s[loaded] / q[loaded]
        if np.ptp(k) > PHASE_TOLERANCE * max(np.max(np.abs(k)), 1e-300):
            raise NotApplicableError(
                "sigma_B / Q changes along the path: the Nowell-Hills closed form needs the "
                "bulk stress in phase with Q (sigma_B = k Q at every step)"
            )
        return float(np.mean(k))

    def _branches(self, tangential: ArrayLike, bulk: ArrayLike):
        """Active branches (scale, sign, c, e) at the end of the path."""
        k = self.ratio(tangential, bulk)
        points = self._md._final(tangential)
        a, fp0 = self.hertz.half_width, self.friction * self.hertz.peak_pressure
        out = []
        for i in range(len(points) - 1):
            delta = points[i + 1] - points[i]
            if delta == 0.0:
                continue
            scale = 1.0 if i == 0 else 2.0
            c = a * self._md._stick_ratio(delta, scale)
            e = self.shift * a * k * abs(delta) / (4.0 * scale * fp0)
            out.append((scale, math.copysign(1.0, delta), c, e))
        return out

    def limit(self, tangential: float) -> float:
        """Largest in-phase |sigma_B| at first loading to Q for which the closed form holds.

        sigma_B <= 4 f p0 (1 - sqrt(1 - |Q|/(f P))), i.e. |e| + c <= a.
        """
        ratio = math.sqrt(max(1.0 - abs(tangential) / self._md.sliding_limit, 0.0))
        return 4.0 * self.friction * self.hertz.peak_pressure * (1.0 - ratio)

    def check(self, tangential: ArrayLike, bulk: ArrayLike) -> None:
        """Raise NotApplicableError unless every active stick zone lies inside the contact."""
        a = self.hertz.half_width
        for _, _, c, e in self._branches(tangential, bulk):
            if abs(e) + c > a * (1.0 + 1e-12):
                raise NotApplicableError(
                    f"the stick zone (offset {e:.4g}, half-width {c:.4g}) leaves the contact "
                    f"(half-width {a:.4g}): one edge reverses slip and no closed form exists"
                )

    def applies(self, tangential: ArrayLike, bulk: ArrayLike) -> str | None:
        """None if the closed form applies to the path, otherwise the reason."""
        try:
            self.check(tangential, bulk)
        except NotApplicableError as err:
            return str(err)
        return None

    def shear_traction(self, x: ArrayLike, tangential: ArrayLike, bulk: ArrayLike) -> np.ndarray:
        """q(x) at the end of the path 0 -> (Q_1, sigma_1) -> ... (checked to apply)."""
        self.check(tangential, bulk)
        x = np.asarray(x, dtype=float)
        a = self.hertz.half_width
        s_a = _ellipse(x, a)
        q = np.zeros_like(x)
        for scale, sign, c, e in self._branches(tangential, bulk):
            q += scale * sign * (s_a - (c / a) * _ellipse(x - e, c))
        return self.friction * self.hertz.peak_pressure * q

    def stick_zone(self, tangential: ArrayLike, bulk: ArrayLike) -> tuple[float, float]:
        """The current (innermost) stick zone (e - c, e + c)."""
        self.check(tangential, bulk)
        branches = self._branches(tangential, bulk)
        if not branches:
            a = self.hertz.half_width
            return (-a, a)
        _, _, c, e = branches[-1]
        return (e - c, e + c)
