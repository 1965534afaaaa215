"""The track a pad slides along: the specimen's face, a straight line or a circular arc.

On a straight track the pad's slide s is an offset of its geometry along the tangent. On a
circular arc (a convex or concave cylindrical specimen) the pad turns about the arc's
centre by theta = s / R as it slides, so it stays normal to the arc and on it; the pair
frame turns with it and the pad's block keeps the pad's own axes, so P acts along the
local normal and Q along the local tangent (:attr:`~fretbem.contact.pairing.Pairing.turn`).
Any other curved face is not a track the pad can follow and is refused.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact.faces import FaceField, FaceProjectionError
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairing import turning
from fretbem.errors import InputError

__all__ = ["ARC", "STRAIGHT", "Track", "TrackError"]

#: how far (a fraction of its length) the specimen's face may depart from its chord and
#: still be a straight track
STRAIGHT = 1e-9
#: how far (a fraction of the radius) the specimen's exact face may depart from the circle
#: through its ends and middle and still be a circular track (NURBS arcs are exact: 1e-15)
ARC = 1e-9
#: samples per segment of the exact face checked against the circle
SAMPLES = 64


class TrackError(InputError):
    """The specimen's face is not a track the pad can slide along."""


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _circle(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, float]:
    """The centre and radius of the circle through three points."""
    matrix = 2.0 * np.array([b - a, c - a])
    rhs = np.array([b @ b - a @ a, c @ c - a @ a])
    centre = np.linalg.solve(matrix, rhs)
    return centre, float(np.linalg.norm(a - centre))


@attrs.frozen(eq=False)
class Track:
    """The specimen's face as a track: where a slide s places the pad, and how far along.

    Attributes
    ----------
    tangent : ndarray, shape (2,)
        The pair tangent where the pad starts (of a straight track: everywhere).
    centre : ndarray, shape (2,) or None
        The arc's centre (None: a straight track).
    rate : float
        d theta / d s, the pad's turn per mm of slide (rad/mm; -1/R on a convex arc slid
        towards +x, +1/R on a concave one; 0 on a straight track).
    start : ndarray, shape (2,)
        The direction from the centre to the pad's start (an arc's), where s = 0.
    """

    tangent: np.ndarray
    centre: np.ndarray | None = None
    rate: float = 0.0
    start: np.ndarray | None = None

    @property
    def straight(self) -> bool:
        """Whether the track is a straight line."""
        return self.centre is None

    @property
    def radius(self) -> float:
        """The arc's radius (mm; infinite for a straight track)."""
        return np.inf if self.straight else 1.0 / abs(self.rate)

    @classmethod
    def of(cls, pair: NodeToSegmentPair) -> Track:
        """The track of ``pair``'s lower face: straight, a circular arc, or refused."""
        if pair.turn:  # a track is read from the pair as drawn
            raise TrackError(
                "finite sliding starts from the pair as drawn; this pair is already turned "
                f"(turn = {pair.turn:.6g} rad): give the pair with turn = 0"
            )
        if pair.frame != "shared":  # the track's frame where the pad starts: the shared one
            pair = attrs.evolve(pair, frame="shared")
        pairing = pair.pairing()
        tangent = np.array(pairing.axes("lower")[1][0])
        body, tag = pair.side("lower")
        points = body.contact_face(tag).points
        chord = points[-1] - points[0] if len(points) > 1 else np.array([1.0, 0.0])
        length = float(np.linalg.norm(chord))
        if length == 0.0:
            return cls(tangent)
        normal = np.array([-chord[1], chord[0]]) / length
        departure = float(np.max(np.abs((points - points[0]) @ normal)))
        if departure <= STRAIGHT * length:
            return cls(tangent)
        _check_models(pair, tag)
        centre, radius = _arc(body, tag, points)
        # the arc's point whose normal is the pair frame's (the frame turns with the pad
        # from there): outward normal radial on a convex arc, towards the centre on a concave
        normal = np.array(pairing.axes("lower")[0][0])
        start = normal if normal @ (points[len(points) // 2] - centre) > 0 else -normal
        _check_start(pair, centre + radius * start, tag)
        rate = float(_cross(start, tangent)) / radius
        return cls(tangent, centre, rate, start)

    def placed(self, pair: NodeToSegmentPair, slide: float) -> NodeToSegmentPair:
        """``pair`` with the pad slid ``slide`` mm along the track from where it was drawn
        (a pair facing nothing stays open: the pad may slide off a face's end)."""
        if self.straight:
            return attrs.evolve(pair, offset=slide * self.tangent, uncovered="open")
        return attrs.evolve(pair, turn=self.rate * slide, pivot=self.centre, uncovered="open")

    def slide_of(self, pair: NodeToSegmentPair) -> float:
        """How far along the track ``pair`` has placed the pad."""
        if self.straight:
            return float(pair.offset @ self.tangent)
        return pair.turn / self.rate

    def along(self, points: np.ndarray) -> np.ndarray:
        """Positions along the track (mm) of points on it: along the tangent, or the arc
        length from the pad's start."""
        points = np.asarray(points, float)
        if self.straight:
            return points @ self.tangent
        radial = points - self.centre
        angle = np.arctan2(_cross(self.start, radial), radial @ self.start)
        return angle / self.rate

    def carried(self, pair: NodeToSegmentPair, block: np.ndarray, shift: float) -> np.ndarray:
        """The pad's block displacement (its axes) that keeps the pad where it is when the
        pairing carries it ``shift`` further along the track: the block gives the slide
        back along its tangent, and on an arc its displacement turns with the pad's axes."""
        tangent = pair.pairing().load_frame("upper")[1]
        block = np.asarray(block, float)
        if not self.straight:
            block = turning(-self.rate * shift) @ block
        return block - shift * tangent


def _arc(body, tag: str, points: np.ndarray) -> tuple[np.ndarray, float]:
    """The centre and radius of a curved face that is a circular arc, else refused."""
    centre, radius = _circle(points[0], points[len(points) // 2], points[-1])
    try:
        field = FaceField.of(body, tag)
    except FaceProjectionError:  # a model without the face's exact geometry: its nodes
        exact = points
    else:
        grid = np.linspace(0.0, 1.0, SAMPLES)
        exact = np.concatenate([b.curve.points(grid) for b in field.segments])
    departure = float(np.max(np.abs(np.linalg.norm(exact - centre, axis=1) - radius)))
    if not departure <= ARC * radius:
        raise TrackError(
            f"finite sliding follows a straight or circular track, but the specimen's face "
            f"{tag!r} is curved and not a circular arc (it departs from the circle through its "
            f"ends and middle, radius {radius:.6g} mm, by {departure:.3g} mm): the pad turns "
            "about the arc's centre as it slides, which only a circle has; slide on a flat or "
            "circular specimen ([specimen] shape = 'flat', 'cylinder' or 'groove'; Python: a "
            "straight or circular lower face)"
        )
    return centre, radius


def _check_start(pair: NodeToSegmentPair, point: np.ndarray, tag: str) -> None:
    """The pad must first touch the arc where its normal is the pair frame's, within a
    pair spacing: the frame that turns with the pad is then the arc's normal at the contact."""
    pairing = pair.pairing()
    gap = pairing.gap
    closest = gap <= gap.min() + 1e-9 * max(float(np.ptp(gap)), 1e-300)
    touch = pairing.points[closest].mean(axis=0)
    spacing = float(np.min(np.linalg.norm(np.diff(pairing.points, axis=0), axis=1)))
    off = float(np.linalg.norm(touch - point))
    if off > spacing:
        raise TrackError(
            f"finite sliding along the arc {tag!r}: the pad first touches it at "
            f"{touch.round(6)}, {off:.4g} mm from {point.round(6)} where the arc's normal is "
            "the pairs' frame (the specimen face's mean normal); the frame turns with the pad "
            "from there, so the pad must start there: centre the specimen's contact face on "
            "the pad"
        )


def _check_models(pair: NodeToSegmentPair, tag: str) -> None:
    """Both bodies must be finite (``bem``) bodies to slide along an arc: a half-plane's
    elasticity is that of the half-plane under a straight surface, fixed in its axes, which
    cannot turn with the pad along the arc."""
    for label, role in (("upper", "pad"), ("lower", "specimen")):
        model = pair.side(label)[0].describe().get("model")
        if model == "half-plane":
            raise TrackError(
                f"finite sliding along the curved face {tag!r} turns the pad with the arc, but "
                f"the {role} is a half-plane body, whose elasticity is that of a half-plane "
                "under a straight surface fixed in its axes, so it cannot turn along an arc; "
                "make both bodies boundary element bodies ([pad] model = 'bem' and [specimen] "
                "model = 'bem'; Python: BEM bodies), or slide on a flat specimen ([specimen] "
                "shape = 'flat')"
            )
