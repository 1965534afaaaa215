"""Closed boundaries made of tagged NURBS segments, checked closed, simple and CCW."""

from __future__ import annotations

from functools import partial

import attrs
import numpy as np

from fretbem.errors import InputError

from .nurbs import NurbsCurve, sample_points


class BoundaryError(InputError):
    """A boundary that does not enclose a region properly (open, crossing or clockwise)."""


@attrs.frozen(eq=False)
class Segment:
    """One tagged piece of a boundary.

    Attributes
    ----------
    tag : str
        Name that boundary conditions and contact pairs refer to ("contact", "top", ...).
        Several segments may share a tag.
    curve : NurbsCurve
        Exact geometry, reparametrised onto [0, 1].
    """

    tag: str = attrs.field(validator=attrs.validators.instance_of(str))
    curve: NurbsCurve = attrs.field(
        converter=lambda c: c.reparametrised((0.0, 1.0)),
        validator=attrs.validators.instance_of(NurbsCurve),
    )
    #: discretisations of this segment by (family, refinement): bodies re-meshed on one
    #: boundary (adaptive and companion levels, sweeps) discretise only what changed
    _discretised: dict = attrs.field(init=False, factory=dict, repr=False, eq=False)

    def discretised(self, family, refinement, discretise=None):
        """``family.discretise(curve, refinement)``, computed once per family and refinement
        (by ``discretise(family, curve, refinement)`` when given: the same basis found
        another way)."""
        key = (family, refinement)
        if key not in self._discretised:
            make = family.discretise if discretise is None else partial(discretise, family)
            self._discretised[key] = make(self.curve, refinement)
        return self._discretised[key]


def _edges(polylines: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Sample edges (m, 2 ends, 2) of all polylines in order, and the segment owning each."""
    edges = np.concatenate([np.stack([line[:-1], line[1:]], axis=1) for line in polylines])
    owner = np.concatenate([np.full(len(line) - 1, k) for k, line in enumerate(polylines)])
    return edges, owner


def _candidate_pairs(edges: np.ndarray, pad: float) -> tuple[np.ndarray, np.ndarray]:
    """Non-adjacent edge pairs (i < j, in row order) whose boxes, grown by ``pad``, overlap.

    Sort and sweep along x, then the y test: every pair the exhaustive tests could flag,
    without forming all m^2 / 2 of them (a boundary of 400 edges has ~1000 candidates).
    """
    lo, hi = edges.min(axis=1) - pad, edges.max(axis=1) + pad
    n = len(edges)
    order = np.argsort(lo[:, 0], kind="stable")
    start_sorted = lo[order, 0]
    reach = np.searchsorted(start_sorted, hi[order, 0], side="right")
    count = np.maximum(reach - np.arange(n) - 1, 0)
    first = np.repeat(np.arange(n), count)
    offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    a, b = order[first], order[first + 1 + offset]
    i, j = np.minimum(a, b), np.maximum(a, b)
    keep = (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1]) & (j - i >= 2)
    keep &= ~((i == 0) & (j == n - 1))  # first and last edges share the closing vertex
    i, j = i[keep], j[keep]
    rank = np.lexsort((j, i))
    return i[rank], j[rank]


def _orient(p, q, r):
    return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
        r[..., 0] - p[..., 0]
    )


def _crossings(edges: np.ndarray, owner: np.ndarray, pairs) -> tuple[int, int] | None:
    """First pair of non-adjacent segments whose sample polylines properly intersect.

    ``pairs``: the candidate edge pairs (:func:`_candidate_pairs` with any pad >= 0: edges
    that cross have overlapping boxes, so a padded superset finds the same first pair).
    """
    a, b = edges[:, 0], edges[:, 1]
    i, j = pairs
    o1 = _orient(a[i], b[i], a[j])
    o2 = _orient(a[i], b[i], b[j])
    o3 = _orient(a[j], b[j], a[i])
    o4 = _orient(a[j], b[j], b[i])
    scale = np.max(np.linalg.norm(b - a, axis=1)) ** 2 * 1e-12
    hit = (o1 * o2 < -scale) & (o3 * o4 < -scale)
    if not np.any(hit):
        return None
    k = int(np.argmax(hit))
    return int(owner[i[k]]), int(owner[j[k]])


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points p to segments a-b (row-wise)."""
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300),
                0.0, 1.0)  # fmt: skip
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def _touching(
    edges: np.ndarray, owner: np.ndarray, pairs, tolerance: float
) -> tuple[int, int, np.ndarray] | None:
    """First pair of non-adjacent sample edges closer than ``tolerance`` (a pinch point);
    ``pairs``: the candidate edge pairs, :func:`_candidate_pairs` padded by ``tolerance``."""
    i, j = pairs
    a, b, c, d = edges[i, 0], edges[i, 1], edges[j, 0], edges[j, 1]
    gap = np.minimum.reduce(
        [_point_segment(c, a, b), _point_segment(d, a, b), _point_segment(a, c, d),
         _point_segment(b, c, d)]
    )  # fmt: skip
    close = gap <= tolerance
    if not np.any(close):
        return None
    k = int(np.argmax(close))
    return int(owner[i[k]]), int(owner[j[k]]), edges[j[k], 0]


@attrs.frozen(eq=False)
class Boundary:
    """A closed, simple, counter-clockwise chain of segments (outward normals on the right).

    Attributes
    ----------
    segments : tuple of Segment
        In order of travel; each ends where the next starts.
    """

    segments: tuple[Segment, ...] = attrs.field(converter=tuple)

    def __attrs_post_init__(self) -> None:
        if not self.segments:
            raise BoundaryError("a boundary needs at least one segment")
        # one evaluation per segment serves every check: its samples include both ends
        polylines = sample_points([s.curve for s in self.segments], np.linspace(0.0, 1.0, 64))
        ends = [(line[0], line[-1]) for line in polylines]
        extent = np.concatenate([s.curve.control_points for s in self.segments])
        size = max(np.ptp(extent, axis=0).max(), 1e-300)
        for k, seg in enumerate(self.segments):
            if np.ptp(seg.curve.control_points, axis=0).max() <= 1e-12 * size:
                raise BoundaryError(
                    f"segment {k} ({seg.tag!r}) has zero length; remove it or give it two "
                    "distinct end points"
                )
            nxt = self.segments[(k + 1) % len(self.segments)]
            gap = np.linalg.norm(ends[k][1] - ends[(k + 1) % len(ends)][0])
            if gap > 1e-9 * size:
                raise BoundaryError(
                    f"boundary is not closed: segment {k} ({seg.tag!r}) ends at {ends[k][1]} but "
                    f"the next segment ({nxt.tag!r}) starts at {ends[(k + 1) % len(ends)][0]} "
                    f"(gap {gap:.3g}); list the segments in order of travel, end to start"
                )
        # one sweep for both checks: the pairs whose boxes come within the pinch tolerance
        edges, owner = _edges(polylines)
        pairs = _candidate_pairs(edges, 1e-9 * size)
        crossing = _crossings(edges, owner, pairs)
        if crossing is not None:
            i, j = crossing
            raise BoundaryError(
                f"boundary crosses itself: segments {i} ({self.segments[i].tag!r}) and {j} "
                f"({self.segments[j].tag!r}) intersect; a body's boundary must be a simple curve"
            )
        touching = _touching(edges, owner, pairs, 1e-9 * size)
        if touching is not None:
            i, j, where = touching
            raise BoundaryError(
                f"boundary touches itself near {np.round(where, 12).tolist()}: segments {i} "
                f"({self.segments[i].tag!r}) and {j} ({self.segments[j].tag!r}) meet at a point "
                "that is not their common end, pinching the body; a body's boundary must be a "
                "simple curve: split the body in two or move the segments apart"
            )
        closed = np.concatenate([p[:-1] for p in polylines])
        x, y = closed[:, 0], closed[:, 1]
        area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
        if area <= 0:
            raise BoundaryError(
                "boundary runs clockwise (signed area "
                f"{area:.4g}); list the segments counter-clockwise so normals point outward, e.g. "
                "with Boundary.reversed()"
            )

    @property
    def tags(self) -> tuple[str, ...]:
        """Tag of every segment, in order."""
        return tuple(s.tag for s in self.segments)

    def indices(self, tag: str) -> list[int]:
        """Indices of the segments carrying ``tag``; an unknown tag is an error listing the tags."""
        found = [k for k, s in enumerate(self.segments) if s.tag == tag]
        if not found:
            raise KeyError(
                f"no boundary segment is tagged {tag!r}; the tags are {sorted(set(self.tags))}"
            )
        return found

    def reversed(self) -> Boundary:
        """The same boundary traversed the other way."""
        return Boundary(tuple(Segment(s.tag, s.curve.reversed()) for s in self.segments[::-1]))

    @classmethod
    def polygon(cls, vertices, tags) -> Boundary:
        """Straight-sided boundary through ``vertices`` (closed automatically), one tag per side."""
        vertices = np.asarray(vertices, float)
        if len(tags) != len(vertices):
            raise ValueError(f"polygon has {len(vertices)} sides but {len(tags)} tags")
        return cls(
            tuple(
                Segment(tag, NurbsCurve.line(vertices[k], vertices[(k + 1) % len(vertices)]))
                for k, tag in enumerate(tags)
            )
        )


@attrs.frozen(eq=False)
class OpenFace:
    """A body's face segments without the closed boundary around them.

    What the scene builder hands a body model that reads only the contact face (the
    half-plane, :attr:`~fretbem.scenes.models.BodyModel.face_only`) of a library shape,
    whose dimensions the shape itself checks: the sides, top or bottom it would never read
    are not built, nor the closed chain checked.

    Attributes
    ----------
    segments : tuple of Segment
        The face's segments in order of travel (flanks and contact).
    """

    segments: tuple[Segment, ...] = attrs.field(converter=tuple)

    @property
    def tags(self) -> tuple[str, ...]:
        """Tag of every segment, in order."""
        return tuple(s.tag for s in self.segments)
