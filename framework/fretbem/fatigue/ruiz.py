"""Ruiz parameters along the contact surface: F1 = tau * delta and F2 = sigma_xx * tau * delta.

Ruiz, Boddington and Chen, "An investigation of fatigue and fretting in a dovetail joint",
Exp. Mech. 24 (1984) 208-217: tau the largest shear traction over the cycle, delta the slip
AMPLITUDE (half the range of the relative tangential displacement over the cycle), sigma_xx the
largest surface stress along the surface over the cycle, taken as zero where it never becomes
tensile (a compressive surface does not open cracks). Ranking only: they carry no life.
"""

from __future__ import annotations

import attrs
import numpy as np

from .errors import FatigueInputError

__all__ = ["RuizParameters", "ruiz_parameters"]


@attrs.frozen(eq=False)
class RuizParameters:
    """F1 and F2 per surface point, with the quantities they are built from.

    Attributes
    ----------
    x : ndarray (S,)
        Surface coordinate, mm.
    shear_traction_max : ndarray (S,)
        max over the cycle of |q|, MPa.
    slip_range, slip_amplitude : ndarray (S,)
        Range and half range of the slip over the cycle, mm.
    surface_stress_xx_max : ndarray (S,)
        max over the cycle of sigma_xx at the surface, MPa.
    f1 : ndarray (S,)
        shear_traction_max * slip_amplitude, N/mm.
    f2 : ndarray (S,)
        max(surface_stress_xx_max, 0) * f1, MPa N/mm.
    """

    x: np.ndarray
    shear_traction_max: np.ndarray
    slip_range: np.ndarray
    slip_amplitude: np.ndarray
    surface_stress_xx_max: np.ndarray
    f1: np.ndarray
    f2: np.ndarray

    @property
    def f2_max_location(self) -> float:
        """x of the largest F2."""
        return float(self.x[int(np.argmax(self.f2))])


def ruiz_parameters(x, shear_traction, surface_stress_xx, slip) -> RuizParameters:
    """Ruiz F1, F2 from histories (T, S) over the cycle at surface points ``x`` (S,)."""
    x = np.asarray(x, dtype=float)
    arrays = [np.asarray(a, dtype=float) for a in (shear_traction, surface_stress_xx, slip)]
    for name, a in zip(("shear_traction", "surface_stress_xx", "slip"), arrays, strict=True):
        if a.ndim != 2 or a.shape[1] != x.size or a.shape[0] < 2:
            raise FatigueInputError(
                f"Ruiz input {name} must have shape (n_steps >= 2, {x.size}), got {a.shape}"
            )
        if not np.all(np.isfinite(a)):
            raise FatigueInputError(f"Ruiz input {name} contains NaN or infinite values")
    q, sxx, s = arrays
    tau = np.abs(q).max(axis=0)
    slip_range = s.max(axis=0) - s.min(axis=0)
    amp = 0.5 * slip_range
    smax = sxx.max(axis=0)
    f1 = tau * amp
    return RuizParameters(
        x=x,
        shear_traction_max=tau,
        slip_range=slip_range,
        slip_amplitude=amp,
        surface_stress_xx_max=smax,
        f1=f1,
        f2=np.maximum(smax, 0.0) * f1,
    )
