"""Wear on a sliding contact: each face's depth on its own material points.

When the pad slides (``[contact] sliding = true``) the pairs move along the specimen, so a
depth per pair no longer belongs to a point of either face. Each face's wear depth is kept
instead on a fixed grid of its own material coordinate: the distance along the track in
the face's position as drawn (the specimen's x, and the pad's x before it moved). A pair
deposits what it wears where it is: on the specimen at its position along the track, on
the pad at that position less the pad's slide. The deposit splits each pair's volume
between the two grid points either side of it (linear hats), so a face's volume
``weights @ depth`` is exactly the sum of the pairs' ``w dh``; reading the depth back at a
pair is the matching linear interpolation.

:class:`WornTrackPair` is the node-to-segment pair with both faces' wear added to its gap,
read at each pair's material points for the pairing's own slide: re-paired at another
slide (:mod:`fretbem.sliding`), it carries its wear with it.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairing import Pairing
from fretbem.validators import float_array

__all__ = ["WornTrackPair", "deposit", "track_grid"]


def track_grid(pair: NodeToSegmentPair) -> tuple[np.ndarray, np.ndarray]:
    """The grid both faces' wear is kept on and its trapezoid weights (mm): uniform, as
    fine as the finer face's nodes, over both faces' extent along the track."""
    tangent = pair.pairing().tangents[0]
    along = [
        np.sort(pair.side(label)[0].contact_face(pair.side(label)[1]).points @ tangent)
        for label in ("upper", "lower")
    ]
    step = min(float(np.min(np.diff(a))) for a in along)
    low = min(a[0] for a in along)
    high = max(a[-1] for a in along)
    n = int(np.ceil((high - low) / step)) + 1
    x = np.linspace(low, high, n)
    weights = np.full(n, (high - low) / (n - 1))
    weights[[0, -1]] *= 0.5
    return x, weights


def deposit(x: np.ndarray, weights: np.ndarray, at: np.ndarray, volume: np.ndarray) -> np.ndarray:
    """Depth on the grid ``x`` (weights ``weights``) of the volumes ``volume`` (mm^3/mm)
    placed at ``at`` (mm), each split linearly between its two neighbouring grid points, so
    that ``weights @ depth == volume.sum()``."""
    at = np.clip(at, x[0], x[-1])
    left = np.clip(np.searchsorted(x, at, side="right") - 1, 0, len(x) - 2)
    t = (at - x[left]) / (x[left + 1] - x[left])
    out = np.zeros(len(x))
    np.add.at(out, left, volume * (1.0 - t))
    np.add.at(out, left + 1, volume * t)
    return out / weights


@attrs.frozen(eq=False)
class WornTrackPair(NodeToSegmentPair):
    """A node-to-segment pair whose gap carries both faces' wear at their material points.

    Attributes
    ----------
    grid : ndarray
        The material coordinate (mm along the track) the depths are given at.
    upper_wear, lower_wear : ndarray
        Wear depth of the pad and of the specimen on ``grid`` (mm).
    datum : float
        Taken off every gap (mm): the pad moved rigidly toward the specimen so that a run
        from the unloaded bodies starts touching (0 during a wear history, whose state
        carries the approach).
    shift : float
        The pad's surface against the specimen's beyond the pairing's slide (mm): the mean
        relative tangential displacement of the pairs in contact when the faces were
        projected. The slide is the loading block's travel, which includes the bodies'
        tangential compliance; the faces' material points meet where the relative
        displacement puts them.
    """

    grid: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    upper_wear: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    lower_wear: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    datum: float = attrs.field(default=0.0, kw_only=True, converter=float)
    shift: float = attrs.field(default=0.0, kw_only=True, converter=float)

    @classmethod
    def of(cls, pair: NodeToSegmentPair, grid, upper, lower, datum=0.0) -> WornTrackPair:
        """``pair`` (its faces, slide and options) with the wear ``upper``, ``lower`` on
        ``grid``."""
        fields = {f.name: getattr(pair, f.name) for f in attrs.fields(NodeToSegmentPair)
                  if f.init}  # fmt: skip
        return cls(**fields, grid=grid, upper_wear=upper, lower_wear=lower, datum=datum)

    def slide(self) -> float:
        """The pad's slide (mm along the track) this pairing was projected at."""
        return float(self.offset @ self._bare().tangents[0])

    def material(self, along: np.ndarray, moved) -> dict:
        """Where the pairs at ``along`` (mm on the track, this pairing's points) are on each
        face's grid when the pad has moved ``moved`` (mm, a relative tangential
        displacement per pair, or a number) against the specimen in this pairing: the pair
        nodes stay on their own face, the other face's point comes to them."""
        if self.slave_side() == "upper":
            return {"lower": along + moved, "upper": along - self.slide()}
        return {"lower": along, "upper": along - self.slide() - moved}

    def wear_gap(self, along: np.ndarray) -> np.ndarray:
        """Both faces' depth (mm) at the pairs at ``along`` (mm on the track), the pad at
        this pairing's slide and ``shift``."""
        at = self.material(along, self.shift)
        lower = np.interp(at["lower"], self.grid, self.lower_wear)
        upper = np.interp(at["upper"], self.grid, self.upper_wear)
        return lower + upper

    def _bare(self) -> Pairing:
        if "bare" not in self._cache:
            self._cache["bare"] = self._pair_up()
        return self._cache["bare"]

    def pairing(self) -> Pairing:
        """The node-to-segment pairing with the worn faces' depths added to its gap."""
        if "pairing" not in self._cache:
            bare = self._bare()
            along = bare.points @ bare.tangents[0]
            worn = np.where(self._cache["covered"], self.wear_gap(along), 0.0)
            self._cache["pairing"] = attrs.evolve(bare, gap=bare.gap + worn - self.datum)
        return self._cache["pairing"]

    def rewear(self, upper: np.ndarray, lower: np.ndarray, shift=None) -> WornTrackPair:
        """This pairing with other depths (and ``shift``, if given): the projection and the
        condensation reused, only the gap differs."""
        shift = self.shift if shift is None else shift
        worn = attrs.evolve(self, upper_wear=upper, lower_wear=lower, shift=shift)
        worn._cache["bare"] = self._bare()
        worn._cache["covered"] = self._cache["covered"]
        if "condensed" in self._cache:
            pairing = worn.pairing()
            worn._cache["condensed"] = attrs.evolve(
                self._cache["condensed"], pair=worn, pairing=pairing, gap=pairing.gap
            )
        return worn

    def touching(self) -> WornTrackPair:
        """This pair with the datum that brings its closest covered pair to touch."""
        worn = self.rewear(self.upper_wear, self.lower_wear)
        gap = worn.pairing().gap[worn._cache["covered"]]
        return attrs.evolve(self, datum=self.datum + float(gap.min()))
