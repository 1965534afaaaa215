"""Wear laws: the wear depth increment of one body from p, q and the slip increment.

Archard's local law dh = k p |ds| (k in 1/MPa) and Fouvry's energy law dh = alpha q |ds|
(alpha in mm^3/J, so dh = 1e-3 alpha |q| |ds| in mm with q in MPa and ds in mm). Each body
has its own law and coefficient: the volume a body loses is its own coefficient times the
summed p |ds| (Archard) or the summed dissipated energy (energy law). Laws are found by
name through the ``fretbem.wear_laws`` entry-point group.
"""

from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod

import attrs
import numpy as np

from fretbem.errors import InputError, ResultCheckError
from fretbem.validators import as_float, shown

__all__ = ["JOULE", "ArchardWear", "EnergyWear", "ScarEdgeError", "WearInputError", "WearLaw"]

#: 1 J in N mm: an energy coefficient in mm^3/J is 1e-3 mm^3/(N mm)
JOULE = 1000.0


class WearInputError(InputError):
    """A wear law, coefficient or wear history that cannot be used."""


class ScarEdgeError(ResultCheckError):
    """The worn contact reached the end pairs of the candidate zone."""

    check = "scar_edge"


def _coefficient(name: str):
    """Converter to a float coefficient >= 0 (booleans and text refused, numpy scalars taken),
    naming ``name``."""

    def convert(value) -> float:
        ok = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
        if not (ok and math.isfinite(as_float(value)) and value >= 0):
            raise WearInputError(
                f"{name} must be a finite number >= 0 (0: the body does not wear), "
                f"got {shown(value)}"
            )
        return float(value)

    return convert


class WearLaw(ABC):
    """How fast one body's surface recedes: a depth increment per pair and increment.

    A law is homogeneous of degree one in the tractions (both built-in laws are), so its
    sensitivity to the pressure is ``depth / p``; a law that is not overrides
    :meth:`pressure_sensitivity` (the cycle-jump stability estimate uses it).
    """

    #: the scene file's name of the law's coefficient
    coefficient_name: str = "coefficient"

    @abstractmethod
    def depth(self, p: np.ndarray, q: np.ndarray, slip: np.ndarray) -> np.ndarray:
        """Wear depth increment (mm, >= 0) per pair for pressure p, shear q (MPa) and the
        slip increment ``slip`` (mm, either sign) of one load increment."""

    def pressure_sensitivity(self, p: np.ndarray, q: np.ndarray, slip: np.ndarray) -> np.ndarray:
        """d(depth)/dp per pair (mm/MPa): ``depth / p`` where p > 0, else 0."""
        p = np.asarray(p, float)
        depth = self.depth(p, q, slip)
        out = np.zeros_like(p)
        touching = p > 0
        out[touching] = depth[touching] / p[touching]
        return out

    @property
    def coefficient(self) -> float:
        """The law's coefficient, as named by :attr:`coefficient_name`."""
        return float(getattr(self, self.coefficient_name))


@attrs.frozen
class ArchardWear(WearLaw):
    """Archard's local law dh = k p |ds|.

    Attributes
    ----------
    k : float
        Local wear coefficient, 1/MPa (mm^3 per N mm of p |ds| per unit area).
    """

    k: float = attrs.field(converter=_coefficient("the Archard coefficient k"))
    coefficient_name = "k"

    def depth(self, p, q, slip) -> np.ndarray:
        """k max(p, 0) |ds|."""
        return self.k * np.maximum(np.asarray(p, float), 0.0) * np.abs(slip)


@attrs.frozen
class EnergyWear(WearLaw):
    """Fouvry's energy law dh = alpha |q| |ds|: a body's wear volume is its alpha times the
    dissipated friction energy.

    Attributes
    ----------
    alpha : float
        Energy wear coefficient of this body, mm^3/J.
    """

    alpha: float = attrs.field(converter=_coefficient("the energy wear coefficient alpha"))
    coefficient_name = "alpha"

    def depth(self, p, q, slip) -> np.ndarray:
        """1e-3 alpha |q| |ds| (alpha in mm^3/J, q in MPa, ds in mm)."""
        touching = np.asarray(p, float) > 0
        return np.where(touching, self.alpha / JOULE * np.abs(q) * np.abs(slip), 0.0)
