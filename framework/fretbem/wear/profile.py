"""The worn profile: wear depth of each face per pair, applied as an offset of the gap.

Wear depths are microns on contacts a millimetre wide, so the bodies' elastic responses
(their condensed contact operators) do not change; only the initial gap does. A
:class:`WornPair` is the pair of a base :class:`~fretbem.contact.pairs.ContactPair` whose
gap is increased by both faces' depths: it reuses the base pair's condensation (no
re-assembly, no re-factorisation) and is a ContactPair like any other, so a worn contact
runs through :func:`fretbem.simulation.run`, the stresses and the fatigue assessment
unchanged. Why an offset rather than a refitted face: docs/explanation/wear.rst.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.pairing import Pairing
from fretbem.contact.pairs import ContactPair
from fretbem.validators import float_array

__all__ = ["BODIES", "WornPair", "WornProfile", "pair_weights"]

#: the bodies of a pair, as labelled in results ("upper" is the pad, "lower" the specimen)
BODIES = ("upper", "lower")


def pair_weights(problem: CondensedContact) -> np.ndarray:
    """Length of face (mm) each pair stands for: the normal force on the lower body per unit
    pressure at that pair, so sum(w p) is exactly the P the contact carries."""
    force = problem.lower_force_map[:, problem.layout.pressure]  # (2, n)
    return -np.einsum("dk,kd->k", force, problem.pairing.normals)


@attrs.frozen(eq=False)
class WornProfile:
    """Accumulated wear depth of each face at the pair points, after ``cycles`` cycles.

    Attributes
    ----------
    x : ndarray
        Pair positions (x of the lower face's points), mm.
    weights : ndarray
        Face length per pair (:func:`pair_weights`), mm.
    upper, lower : ndarray
        Wear depth of the pad and of the specimen, mm (>= 0, along the pair normal).
    cycles : int
    upper_x, upper_weights : ndarray or None
        The pad's own points and their face lengths when they differ from ``x`` and
        ``weights`` (finite sliding: each face's depth at its own material points,
        :mod:`fretbem.wear.track`); None: the pairs'.
    """

    x: np.ndarray = attrs.field(converter=float_array)
    weights: np.ndarray = attrs.field(converter=float_array)
    upper: np.ndarray = attrs.field(converter=float_array)
    lower: np.ndarray = attrs.field(converter=float_array)
    cycles: int = 0
    upper_x: np.ndarray | None = None
    upper_weights: np.ndarray | None = None

    def grid(self, body: str) -> tuple[np.ndarray, np.ndarray]:
        """The points (mm) ``body``'s depths are given at and their face lengths (mm)."""
        if body == "upper" and self.upper_x is not None:
            return self.upper_x, self.upper_weights
        return self.x, self.weights

    @classmethod
    def unworn(cls, problem: CondensedContact) -> WornProfile:
        """No wear yet, on the pairs of ``problem``."""
        n = problem.n_pairs
        x = problem.pairing.points[:, 0]
        return cls(x, pair_weights(problem), np.zeros(n), np.zeros(n))

    def depth(self, body: str) -> np.ndarray:
        """Wear depth of ``body`` ("upper" or "lower")."""
        return {"upper": self.upper, "lower": self.lower}[body]

    @property
    def offset(self) -> np.ndarray:
        """Gap offset: both faces receded, so the gap grows by the sum of the depths."""
        return self.upper + self.lower

    def worn(self, cycles: int, upper: np.ndarray, lower: np.ndarray) -> WornProfile:
        """The profile after further depths ``upper``, ``lower`` added, at ``cycles``."""
        return attrs.evolve(self, upper=self.upper + upper, lower=self.lower + lower, cycles=cycles)

    def volume(self, body: str) -> float:
        """Worn volume of ``body`` per unit thickness, mm^3/mm."""
        return float(self.grid(body)[1] @ self.depth(body))

    def max_depth(self, body: str) -> float:
        """Largest wear depth of ``body``, mm."""
        return float(np.max(self.depth(body), initial=0.0))

    def scar(self, body: str, level: float = 0.01) -> tuple[float, float]:
        """(x_min, x_max) of the pairs where ``body`` is worn deeper than ``level`` times its
        largest depth; (nan, nan) when it is not worn."""
        depth = self.depth(body)
        top = np.max(depth, initial=0.0)
        if not top > 0:
            return float("nan"), float("nan")
        worn = self.grid(body)[0][depth > level * top]
        return float(worn.min()), float(worn.max())

    def scar_width(self, body: str, level: float = 0.01) -> float:
        """Width of the scar of ``body`` (see :meth:`scar`), mm; 0 when it is not worn."""
        low, high = self.scar(body, level)
        return 0.0 if np.isnan(low) else high - low


@attrs.frozen(eq=False)
class WornPair(ContactPair):
    """A contact pair whose gap is the base pair's plus a wear offset per pair.

    Build it with :meth:`of`. The condensation is the base pair's (computed once for all
    profiles); only the gap differs.

    Attributes
    ----------
    base : ContactPair
        The unworn pair.
    offset : ndarray
        Gap offset per pair (both faces' wear depths summed), mm.
    touching : bool
        Take away the smallest gap, so the closest pairs touch: the pad moved rigidly
        toward the specimen, which changes nothing when P is imposed and lets a solution
        start from the unloaded bodies (the solvers' first contact is at zero gap). Not for
        an imposed normal approach, whose datum it would move.
    """

    base: ContactPair = attrs.field(kw_only=True)
    offset: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    touching: bool = attrs.field(default=False, kw_only=True)

    @classmethod
    def of(cls, base: ContactPair, offset: np.ndarray, touching: bool = False) -> WornPair:
        """``base`` (or the unworn pair under a WornPair) with the gap offset ``offset``."""
        while isinstance(base, WornPair):
            base = base.base
        return cls(base.upper, base.lower, base.upper_tag, base.lower_tag,
                   base=base, offset=offset, touching=touching)  # fmt: skip

    def pairing(self) -> Pairing:
        """The base pairing with the gap increased by the offset."""
        if "pairing" not in self._cache:
            base = self.base.pairing()
            if self.offset.shape != base.gap.shape:
                raise ValueError(
                    f"a wear offset of shape {self.offset.shape} does not fit the "
                    f"{base.n_pairs} pairs of the contact"
                )
            gap = base.gap + self.offset
            if self.touching:
                gap = gap - gap.min()
            self._cache["pairing"] = attrs.evolve(base, gap=gap)
        return self._cache["pairing"]

    def condensed(self) -> CondensedContact:
        """The base pair's condensation with this pairing's gap (no new condensation)."""
        if "condensed" not in self._cache:
            pairing = self.pairing()
            self._cache["condensed"] = attrs.evolve(
                self.base.condensed(), pair=self, pairing=pairing, gap=pairing.gap
            )
        return self._cache["condensed"]
