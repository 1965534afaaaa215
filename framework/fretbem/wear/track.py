"""Wear on a sliding contact: each face's depth on its own material points.

When the pad slides (``[contact] sliding = true``) the pairs move along the other face, so
a depth per pair no longer belongs to a point of both faces. Each face's depth is kept at
its own material points, in the face's coordinate as drawn (the specimen's x, the pad's x
before it slid):

* the face whose nodes are the pairs (the slave, by default the coarser pad) at those
  nodes: pair k always stands for the same node, so its depth is the pair's own;
* the other face on a uniform grid along the track, four points a pair spacing. A pair's
  increment of wear is spread over what it swept on that face in the increment (its face
  length, carried from where it met the face at the increment's start to where it met it
  at the end) and split linearly between grid points, so that the face's volume
  ``weights @ depth`` is exactly the sum of the pairs' ``w dh``.

The gap of a pairing reads each face's depth back at its pairs' material points
(:class:`WornTrackPair`); re-projected at another slide, it carries its wear along.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairing import Pairing
from fretbem.sliding import track as sliding_track
from fretbem.validators import float_array

__all__ = ["GRID_DENSITY", "WornTrackPair", "deposit", "spread", "track_grids"]

#: grid points a pair spacing on the face the pairs slide along
GRID_DENSITY = 4


def track_grids(
    pair: NodeToSegmentPair, weights: np.ndarray, path: sliding_track.Track | None = None
) -> dict:
    """Each face's points along the track and their face lengths (mm), "upper" and
    "lower": the slave face's are its nodes (the pairs at the pair's slide, and
    ``weights``, the pairs' face lengths); the other face's a uniform grid over its
    extent, :data:`GRID_DENSITY` points a pair spacing, with trapezoid weights. Along a
    circular ``path`` (:class:`~fretbem.sliding.track.Track`) the positions are arc lengths
    on the specimen's face; None or a straight one: along the pairs' tangent."""
    pairing = pair.pairing()
    slave = pair.slave_side()
    if path is None or path.straight:
        tangent = pairing.tangents[0]
        along = pairing.points @ tangent
        slide = float(pair.offset @ tangent)
    else:
        along, slide = path.along(pairing.points), path.slide_of(pair)
    spacing = float(np.min(np.diff(along)))
    grids = {slave: (along - (slide if slave == "upper" else 0.0), np.asarray(weights, float))}
    master = "upper" if slave == "lower" else "lower"
    body, tag = pair.side(master)
    drawn = body.contact_face(tag).points
    face = np.sort(drawn @ tangent if path is None or path.straight else path.along(drawn))
    n = int(np.ceil((face[-1] - face[0]) * GRID_DENSITY / spacing)) + 1
    x = np.linspace(face[0], face[-1], n)
    step = np.full(n, (face[-1] - face[0]) / (n - 1))
    step[[0, -1]] *= 0.5
    grids[master] = (x, step)
    return grids


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


def spread(x, weights, start, end, width, volume) -> np.ndarray:
    """Depth on the grid ``x`` of the volumes ``volume`` spread evenly over what each pair
    swept: its face length ``width`` carried from ``start`` to ``end`` (mm), sampled at
    half the grid's spacing; ``weights @ depth == volume.sum()``."""
    half = 0.5 * float(x[1] - x[0])
    m_path = max(1, int(np.ceil(np.max(np.abs(end - start), initial=0.0) / half)))
    m_width = max(1, int(np.ceil(np.max(width, initial=0.0) / half)))
    u = (np.arange(m_path) + 0.5) / m_path
    v = (np.arange(m_width) + 0.5) / m_width - 0.5
    at = (start[:, None, None] + u[None, :, None] * (end - start)[:, None, None]
          + v[None, None, :] * width[:, None, None])  # fmt: skip
    share = np.broadcast_to((volume / (m_path * m_width))[:, None, None], at.shape)
    return deposit(x, weights, at.ravel(), share.ravel())


@attrs.frozen(eq=False)
class WornTrackPair(NodeToSegmentPair):
    """A node-to-segment pair whose gap carries both faces' wear at their material points.

    Attributes
    ----------
    upper_grid, lower_grid : ndarray
        Each face's material points (mm along the track, the face as drawn) its depth is
        given at (:func:`track_grids`).
    upper_wear, lower_wear : ndarray
        Wear depth of the pad and of the specimen at those points (mm).
    path : fretbem.sliding.track.Track or None
        The track the pad slides along (:class:`~fretbem.sliding.track.Track`): a circular
        one measures positions in arc length on the specimen's face and the slide by the
        pad's turn; None: a straight one, along the pairs' tangent.
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

    upper_grid: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    lower_grid: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    upper_wear: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    lower_wear: np.ndarray = attrs.field(kw_only=True, converter=float_array)
    path: sliding_track.Track | None = attrs.field(default=None, kw_only=True)
    datum: float = attrs.field(default=0.0, kw_only=True, converter=float)
    shift: float = attrs.field(default=0.0, kw_only=True, converter=float)

    @classmethod
    def of(cls, pair: NodeToSegmentPair, grids: dict, upper, lower, path=None) -> WornTrackPair:
        """``pair`` (its faces, slide and options) with the wear ``upper``, ``lower`` at
        the points ``grids[body][0]``, sliding along ``path``."""
        fields = {f.name: getattr(pair, f.name) for f in attrs.fields(NodeToSegmentPair)
                  if f.init}  # fmt: skip
        return cls(**fields, upper_grid=grids["upper"][0], lower_grid=grids["lower"][0],
                   upper_wear=upper, lower_wear=lower, path=path)  # fmt: skip

    @property
    def straight(self) -> bool:
        """Whether the pad slides along a straight track."""
        return self.path is None or self.path.straight

    def slide(self) -> float:
        """The pad's slide (mm along the track) this pairing was projected at."""
        if self.straight:
            return float(self.offset @ self._bare().tangents[0])
        return self.path.slide_of(self)

    def along(self, points: np.ndarray) -> np.ndarray:
        """Positions (mm along the track) of points on the specimen's face: along the
        pairs' tangent, or the arc length of a circular track."""
        if self.straight:
            return points @ self._bare().tangents[0]
        return self.path.along(points)

    def material(self, along: np.ndarray, moved) -> dict:
        """Where the pairs at ``along`` (mm on the track, this pairing's points) are on each
        face's grid when the pad has moved ``moved`` (mm, a relative tangential
        displacement per pair, or a number) against the specimen in this pairing: the pair
        nodes stay on their own face, the other face's point comes to them."""
        if self.slave_side() == "upper":
            return {"lower": along + moved, "upper": along - self.slide()}
        return {"lower": along, "upper": along - self.slide() - moved}

    def wear_gap(self, along: np.ndarray) -> np.ndarray:
        """Both faces' depth (mm) at the pairs at ``along`` (mm on the track, in order), the
        pad at this pairing's slide and ``shift``: the slave face's at its nodes, the
        other's read on its grid where the pairs meet it."""
        at = self.material(along, self.shift)
        slave = self.slave_side()
        total = np.array(self.upper_wear if slave == "upper" else self.lower_wear)
        master = "upper" if slave == "lower" else "lower"
        grid = {"upper": self.upper_grid, "lower": self.lower_grid}[master]
        wear = {"upper": self.upper_wear, "lower": self.lower_wear}[master]
        return total + np.interp(at[master], grid, wear)

    def _bare(self) -> Pairing:
        if "bare" not in self._cache:
            self._cache["bare"] = self._pair_up()
        return self._cache["bare"]

    def pairing(self) -> Pairing:
        """The node-to-segment pairing with the worn faces' depths added to its gap."""
        if "pairing" not in self._cache:
            bare = self._bare()
            along = self.along(bare.points)
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
