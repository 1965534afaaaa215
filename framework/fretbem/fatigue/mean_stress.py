"""Mean-stress corrections of the stress-life and strain-life curves (Goodman, Gerber, Morrow).

The stress-based corrections turn a cycle of amplitude sigma_a and mean sigma_m into the fully
reversed amplitude sigma_ar that does the same damage, read on the Basquin curve
sigma_ar = sigma_f' (2N)^b:

- Goodman: sigma_ar = sigma_a / (1 - sigma_m / sigma_u)
- Gerber: sigma_ar = sigma_a / (1 - (sigma_m / sigma_u)^2)
- Morrow: sigma_ar = sigma_a / (1 - sigma_m / sigma_f')
- Morrow with the true fracture strength: sigma_ar = sigma_a / (1 - sigma_m / sigma~_fB)

(N. E. Dowling, Mechanical Behavior of Materials, 4th ed., Pearson 2013, ch. 9; the same
equations as the test cases of the open FatPy project, faberorg/FatPy issues 37 and 38). The
strain-life Morrow correction lowers the elastic term: eps_a = (sigma_f' - sigma_m)/E (2N)^b +
eps_f' (2N)^c. Each equation is applied as published at either sign of sigma_m: Gerber's
parabola is symmetric (a compressive mean is as harmful as a tensile one, conservative),
Goodman and Morrow credit a compressive mean. A mean stress at or beyond the limit stress
(the denominator reaches zero) is a static failure: sigma_ar = inf. SWT, Findley,
Fatemi-Socie and MWCM carry the mean stress in their own parameters and take no correction.
"""

from __future__ import annotations

import attrs
import numpy as np

from .errors import FatigueInputError
from .material import FatigueMaterial

__all__ = [
    "CORRECTIONS",
    "CORRECTIONS_OF",
    "MeanStressCorrection",
    "mean_stress_correction",
]

#: each correction: (the material constant it divides the mean stress by, meaning)
CORRECTIONS: dict[str, tuple[str | None, str]] = {
    "none": (None, "no correction: the amplitude alone"),
    "goodman": ("ultimate_strength", "sigma_a / (1 - sigma_m / sigma_u)"),
    "gerber": ("ultimate_strength", "sigma_a / (1 - (sigma_m / sigma_u)^2)"),
    "morrow": ("fatigue_strength_coefficient", "sigma_a / (1 - sigma_m / sigma_f')"),
    "morrow_true_fracture": (
        "true_fracture_strength",
        "sigma_a / (1 - sigma_m / sigma~_fB), the true fracture strength",
    ),
}

#: the corrections each life method takes (the other methods carry the mean stress themselves)
CORRECTIONS_OF: dict[str, tuple[str, ...]] = {
    "stress_life": ("none", "goodman", "gerber", "morrow", "morrow_true_fracture"),
    "strain_life": ("none", "morrow"),
}


@attrs.frozen
class MeanStressCorrection:
    """A mean-stress correction and the limit stress it uses.

    Attributes
    ----------
    name : str
        One of :data:`CORRECTIONS`.
    limit : float or None
        The stress the mean is divided by (MPa): sigma_u, sigma_f' or sigma~_fB; None for
        ``"none"``.
    """

    name: str = "none"
    limit: float | None = None

    def __attrs_post_init__(self) -> None:
        if self.name not in CORRECTIONS:
            raise FatigueInputError(
                f"unknown mean-stress correction {self.name!r}; choose from {sorted(CORRECTIONS)}"
            )
        if (self.name == "none") != (self.limit is None):
            raise FatigueInputError(
                f"the {self.name!r} mean-stress correction "
                + ("takes no limit stress" if self.name == "none" else "needs its limit stress")
            )
        if self.limit is not None and not (np.isfinite(self.limit) and self.limit > 0):
            raise FatigueInputError(
                f"the {self.name!r} mean-stress correction needs a limit stress > 0 MPa "
                f"({CORRECTIONS[self.name][0]}), got {self.limit}"
            )

    def equivalent_amplitude(self, amplitude, mean):
        """sigma_ar of cycles with ``amplitude`` and ``mean`` (MPa); inf where the mean
        reaches the limit stress (a static failure)."""
        amplitude = np.asarray(amplitude, dtype=float)
        if self.name == "none":
            return amplitude + 0.0 * np.asarray(mean, dtype=float)
        ratio = np.asarray(mean, dtype=float) / self.limit
        factor = 1.0 - ratio**2 if self.name == "gerber" else 1.0 - ratio
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(factor > 0.0, amplitude / np.where(factor > 0, factor, 1.0), np.inf)

    def static_failure(self, mean: float) -> bool:
        """Whether the mean stress reaches the limit stress (no fatigue life at all)."""
        if self.name == "none":
            return False
        ratio = mean / self.limit
        return (1.0 - ratio**2 if self.name == "gerber" else 1.0 - ratio) <= 0.0


def mean_stress_correction(name: str, material: FatigueMaterial) -> MeanStressCorrection:
    """The correction ``name`` with its limit stress from ``material``; a missing constant
    raises :class:`~fretbem.fatigue.errors.MissingFatigueDataError` naming it."""
    if name not in CORRECTIONS:
        raise FatigueInputError(
            f"unknown mean-stress correction {name!r}; choose from {sorted(CORRECTIONS)}"
        )
    key = CORRECTIONS[name][0]
    if key is None:
        return MeanStressCorrection()
    limit = material.require((key,), f"the {name} mean-stress correction")[key]
    return MeanStressCorrection(name, limit)
