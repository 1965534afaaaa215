"""A small library of pad and specimen shapes: exact NURBS boundaries with standard tags.

A pad (the upper body) has its contact face at the bottom, lowest point at the origin, and a
``top`` edge where the loading block acts. A specimen (the lower body) has its face at
y = 0. Each face is split into ``flank_left``, ``contact`` and ``flank_right``: the
``contact`` segments span the candidate zone (x from -zone to +zone) and hold the node
pairs; the specimen's contact segments are built from the pad's (mirrored or flattened,
keeping the pad's x(xi)), so equal refinement gives points that face each other.

Tags: pad ``flank_left, contact, flank_right, side_right, top, side_left``; flat specimen
``bottom, end_right, flank_right, contact, flank_left, end_left``; cylindrical and grooved
specimens ``bottom, side_right, flank_right, contact, flank_left, side_left``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.validators import number_field

from .boundary import Boundary, Segment
from .nurbs import NurbsCurve

__all__ = [
    "CylinderPad",
    "CylinderSpecimen",
    "FlatSpecimen",
    "GrooveSpecimen",
    "NurbsShape",
    "RoundedFlatPad",
    "ShapeError",
]


class ShapeError(InputError):
    """Dimensions that do not make the shape (e.g. a zone wider than the face)."""


def _length(what: str):
    """Converter of a shape's length: a finite number > 0 in mm, ShapeError naming the field."""
    return number_field(
        f"{what}, mm", "give it in mm, > 0", low=0.0, low_open=True, error=ShapeError
    )


#: curve parameters at which a cylinder specimen's contact arc is compared with the pad's
_FACING_SAMPLES = np.linspace(0.0, 1.0, 7)
_FACING_SAMPLES.setflags(write=False)


def _arcs(center: Sequence[float], radius: float, angles: Sequence[float]) -> list[NurbsCurve]:
    return [NurbsCurve.arc(center, radius, a0, a1) for a0, a1 in itertools.pairwise(angles)]


def _face_tags(curves_left_to_right: list[list[NurbsCurve]]) -> list[Segment]:
    """Segments flank_left / contact / flank_right from curve groups ordered left to right."""
    left, contact, right = curves_left_to_right
    return (
        [Segment("flank_left", c) for c in left]
        + [Segment("contact", c) for c in contact]
        + [Segment("flank_right", c) for c in right]
    )


def _arc_specimen_face(arcs: list[NurbsCurve]) -> list[Segment]:
    """A specimen face of three arcs right to left: flank, contact, flank."""
    return [Segment("flank_right", arcs[0]), Segment("contact", arcs[1]),
            Segment("flank_left", arcs[2])]  # fmt: skip


def _mirrored(curve: NurbsCurve) -> NurbsCurve:
    """``curve`` reflected about x = 0 and traversed the other way (the same direction
    around the body): exactly, coordinate by coordinate."""
    back = curve.reversed()
    points = back.control_points * [-1.0, 1.0] + 0.0  # + 0.0: x = 0 stays 0, not -0
    return NurbsCurve.exact_image(back, back.knots, points, back.weights)


def _symmetric(curve: NurbsCurve) -> NurbsCurve:
    """A curve symmetric about x = 0 to round-off made symmetric to the last bit: each
    control point and weight the mean of itself and its mirror (uniform knots assumed
    symmetric, as an arc's are)."""
    points, weights = curve.control_points, curve.weights
    x = (points[:, 0] - points[::-1, 0]) * 0.5 + 0.0
    y = (points[:, 1] + points[::-1, 1]) * 0.5
    return NurbsCurve.exact_image(
        curve, curve.knots, np.column_stack([x, y]), (weights + weights[::-1]) * 0.5
    )


def _within(a: np.ndarray, b: np.ndarray, atol: float, rtol: float = 0.0) -> bool:
    """``np.allclose(a, b, rtol, atol)`` for finite arrays of one shape: |a - b| <= atol +
    rtol |b| everywhere, without allclose's broadcasting and special values (a third of its
    cost on a curve's few control points; a scene build asks four times)."""
    return bool(np.logical_and.reduce(np.abs(a - b) <= atol + rtol * np.abs(b), axis=None))


def _point_image(pad_curve: NurbsCurve, own: NurbsCurve, radius: float) -> NurbsCurve:
    """``own`` (a specimen arc), or the pad's face curve reflected through the origin when
    that is the same arc to round-off (a specimen as wide as the pad): the two similar
    cylinders are then each other's exact point image, which the BEM assembly uses (one
    body's blocks serve the other's, :class:`fretbem.bem.assembly.BlockStore`)."""
    image = -pad_curve.control_points + 0.0  # + 0.0: a coordinate 0 stays 0, not -0
    same = (
        pad_curve.degree == own.degree
        and image.shape == own.control_points.shape
        and np.array_equal(pad_curve.knots, own.knots)
        and np.array_equal(pad_curve.weights, own.weights)
        and _within(image, own.control_points, 1e-12 * radius)
    )
    return NurbsCurve.exact_image(own, own.knots, image, own.weights) if same else own


def _arc_specimen_boundary(face: list[Segment], half: float, h: float) -> Boundary:
    """A specimen whose face is three arcs right to left (:func:`_arc_specimen_face`)
    between vertical sides, its bottom at y = -h: the cylinder's and the groove's."""
    return Boundary(
        [
            Segment("bottom", NurbsCurve.line([-half, -h], [half, -h])),
            Segment("side_right", NurbsCurve.line([half, -h], face[0].curve.points([0.0])[0])),
            *face,
            Segment("side_left", NurbsCurve.line(face[-1].curve.points([1.0])[0], [-half, -h])),
        ]
    )


def _pad_boundary(face: list[Segment], half_width: float, height: float) -> Boundary:
    left = face[0].curve.points([0.0])[0]
    right = face[-1].curve.points([1.0])[0]
    return Boundary(
        [
            *face,
            Segment("side_right", NurbsCurve.line(right, [half_width, height])),
            Segment("top", NurbsCurve.line([half_width, height], [-half_width, height])),
            Segment("side_left", NurbsCurve.line([-half_width, height], left)),
        ]
    )


def _check_sag(what: str, radius: float, width: float, height: float) -> None:
    """The body must be higher than its curved face drops over its width (the sag), or its
    flank would cross its top (or bottom) edge."""
    half = min(width / 2, radius)
    sag = radius - math.sqrt(max(radius * radius - half * half, 0.0))
    if not height > sag:
        raise ShapeError(
            f"a {what} {height:g} mm high is lower than its face's sag over its width "
            f"({sag:.4g} mm = R - sqrt(R^2 - (w/2)^2)), so the face would cross its "
            f"{'top' if what == 'pad' else 'bottom'}; make height > {sag:.4g} mm or the width "
            "smaller"
        )


def _check_zone(zone: float, half_width: float, what: str) -> None:
    if not 0.0 < zone < half_width:
        raise ShapeError(
            f"the candidate contact zone (half-width {zone:.4g} mm) must lie inside the "
            f"{what} face (half-width {half_width:.4g} mm); lower [contact] zone (or zone_width) "
            f"or widen the {what}"
        )


@attrs.frozen
class CylinderPad:
    """A pad whose face is a circular arc of radius R (lowest point at the origin).

    Attributes
    ----------
    radius, width, height : float
        R, the pad's width w (x from -w/2 to w/2) and height h (top edge at y = h), mm.
    """

    radius: float = attrs.field(converter=_length("the face's radius R"))
    width: float = attrs.field(converter=_length("the width w"))
    height: float = attrs.field(converter=_length("the height h"))
    kind = "cylinder"

    def __attrs_post_init__(self) -> None:
        if self.width / 2 >= self.radius:
            raise ShapeError(
                f"a cylinder pad of radius {self.radius:g} mm cannot be {self.width:g} mm wide "
                "(the face would pass the arc's quarter point); make width < 2 radius"
            )
        _check_sag("pad", self.radius, self.width, self.height)

    @property
    def curvature(self) -> float:
        """1/R of the face at the first contact point (for Hertz)."""
        return 1.0 / self.radius

    def face(self, zone: float) -> list[Segment]:
        """Face segments left to right, the contact segment spanning |x| <= zone."""
        _check_zone(zone, self.width / 2, "pad")
        r = self.radius
        phi_w, phi_z = math.asin(self.width / 2 / r), math.asin(zone / r)
        down = -math.pi / 2
        # the left flank and the contact arc: the right flank is the left one mirrored
        arcs = _arcs([0.0, r], r, [down - phi_w, down - phi_z, down + phi_z])
        # symmetric about x = 0 to the last bit (the arcs' cosines and sines are not): the
        # right flank the left one mirrored, the contact arc its mean with its mirror
        return _face_tags([[arcs[0]], [_symmetric(arcs[1])], [_mirrored(arcs[0])]])

    def boundary(self, zone: float, face: Sequence[Segment] | None = None) -> Boundary:
        """The closed pad boundary (face, sides, top); ``face``: the segments of
        ``face(zone)`` when the caller has built them already (they are used as they are)."""
        face = self.face(zone) if face is None else list(face)
        return _pad_boundary(face, self.width / 2, self.height)


@attrs.frozen
class RoundedFlatPad:
    """A pad with a flat of half-width b and circular fillets of radius r on both sides.

    The face is straight for |x| <= b and follows the fillets beyond (C1 at x = +-b), the
    punch of Ciavarella, Hills and Monno (1998). The candidate zone must cover the flat.

    Attributes
    ----------
    flat, edge_radius, width, height : float
        b, r, the pad's width w and height h, mm.
    """

    flat: float = attrs.field(converter=_length("the flat's half-width b"))
    edge_radius: float = attrs.field(converter=_length("the fillets' radius r"))
    width: float = attrs.field(converter=_length("the width w"))
    height: float = attrs.field(converter=_length("the height h"))
    kind = "rounded-flat"

    def __attrs_post_init__(self) -> None:
        if not self.flat < self.width / 2 < self.flat + self.edge_radius:
            raise ShapeError(
                f"a rounded-flat pad needs flat < width/2 < flat + edge_radius (got flat "
                f"{self.flat:g}, width/2 {self.width / 2:g}, edge_radius {self.edge_radius:g})"
            )
        r, x = self.edge_radius, self.width / 2 - self.flat
        _check_sag("pad", r, 2 * x, self.height)

    @property
    def curvature(self) -> float:
        """Zero: the face is flat at the first contact (no Hertz reference)."""
        return 0.0

    def _fillet(self, side: float, x0: float, x1: float) -> NurbsCurve:
        b, r = self.flat, self.edge_radius
        down = -math.pi / 2
        angles = [down + math.asin((abs(x) - b) / r) * side for x in (x0, x1)]
        return NurbsCurve.arc([side * b, r], r, *angles)

    def face(self, zone: float) -> list[Segment]:
        """Fillet, flat, fillet: the contact segments span |x| <= zone (zone > flat)."""
        _check_zone(zone, self.width / 2, "pad")
        if zone <= self.flat:
            raise ShapeError(
                f"the candidate zone (half-width {zone:.4g} mm) must cover the flat "
                f"(half-width {self.flat:g} mm): raise 'zone'"
            )
        w2, b = self.width / 2, self.flat
        left = [self._fillet(-1.0, -w2, -zone)]
        contact = [
            self._fillet(-1.0, -zone, -b),
            NurbsCurve.line([-b, 0.0], [b, 0.0]),
            self._fillet(1.0, b, zone),
        ]
        right = [self._fillet(1.0, zone, w2)]
        return _face_tags([left, contact, right])

    def boundary(self, zone: float, face: Sequence[Segment] | None = None) -> Boundary:
        """The closed pad boundary (face, sides, top); ``face``: the segments of
        ``face(zone)`` when the caller has built them already (they are used as they are)."""
        face = self.face(zone) if face is None else list(face)
        return _pad_boundary(face, self.width / 2, self.height)


def _specimen_face(pad_face: list[Segment], transform, half_width: float) -> list[Segment]:
    """Specimen face segments right to left (CCW), contact built from the pad's contact."""
    contact = [transform(s.curve).reversed() for s in pad_face if s.tag == "contact"][::-1]
    right_end = contact[0].points([0.0])[0]
    left_end = contact[-1].points([1.0])[0]
    return (
        [Segment("flank_right", NurbsCurve.line([half_width, right_end[1]], right_end))]
        + [Segment("contact", c) for c in contact]
        + [Segment("flank_left", NurbsCurve.line(left_end, [-half_width, left_end[1]]))]
    )


@attrs.frozen
class FlatSpecimen:
    """A flat specimen of length L and thickness t, face at y = 0, held and pulled at its ends.

    Attributes
    ----------
    length, thickness : float
        L (x from -L/2 to L/2) and t (bottom at y = -t), mm.
    """

    length: float = attrs.field(converter=_length("the length L"))
    thickness: float = attrs.field(converter=_length("the thickness t"))
    kind = "flat"

    @property
    def curvature(self) -> float:
        """Zero: a flat face."""
        return 0.0

    def face(self, pad_face: Sequence[Segment], zone: float) -> list[Segment]:
        """The face right to left: the contact segments facing the pad's (its contact
        flattened onto y = 0) between straight flanks to the ends; what :meth:`boundary`
        checks of the dimensions, without building the closed boundary (a model that reads
        only the face, the half-plane)."""
        half = self.length / 2
        _check_zone(zone, half, "specimen")
        # the flanks of a flat face are straight: exact lines from the contact ends
        return _specimen_face(pad_face, lambda c: c.flattened(0.0), half)

    def boundary(self, pad_face: list[Segment], zone: float) -> Boundary:
        """Bottom, the pulled +x end, the face (contact facing the pad's), the held -x end."""
        half, t = self.length / 2, self.thickness
        face = self.face(pad_face, zone)
        return Boundary(
            [
                Segment("bottom", NurbsCurve.line([-half, -t], [half, -t])),
                Segment("end_right", NurbsCurve.line([half, -t], [half, 0.0])),
                *face,
                Segment("end_left", NurbsCurve.line([-half, 0.0], [-half, -t])),
            ]
        )


@attrs.frozen
class CylinderSpecimen:
    """A specimen whose face is the mirror image of a cylinder pad (two similar cylinders).

    Attributes
    ----------
    radius, width, height : float
        R (equal to the pad's), width w and height h (bottom at y = -h), mm.
    """

    radius: float = attrs.field(converter=_length("the face's radius R"))
    width: float = attrs.field(converter=_length("the width w"))
    height: float = attrs.field(converter=_length("the height h"))
    kind = "cylinder"

    def __attrs_post_init__(self) -> None:
        if self.width / 2 < self.radius:
            _check_sag("specimen", self.radius, self.width, self.height)

    @property
    def curvature(self) -> float:
        """1/R of the face at the first contact point."""
        return 1.0 / self.radius

    def face(self, pad_face: Sequence[Segment], zone: float) -> list[Segment]:
        """The arc face right to left (flank, contact, flank), the pad's face mirrored about
        y = 0; what :meth:`boundary` checks, without building the closed boundary."""
        half, r = self.width / 2, self.radius
        _check_zone(zone, half, "specimen")
        if half >= r:
            raise ShapeError(
                f"a cylinder specimen of radius {r:g} mm cannot be {self.width:g} mm wide; "
                "make width < 2 radius"
            )
        phi_w, phi_z = math.asin(half / r), math.asin(zone / r)
        up = math.pi / 2
        arcs = _arcs([0.0, -r], r, [up - phi_w, up - phi_z, up + phi_z, up + phi_w])
        contact = [s.curve for s in pad_face if s.tag == "contact"]
        samples = _FACING_SAMPLES
        if len(contact) != 1 or not _within(
            contact[0].points(samples)[:, 0], arcs[1].points(samples[::-1])[:, 0], 1e-9 * r, 1e-5
        ):
            raise ShapeError(
                f"a cylinder specimen (radius {r:g} mm) faces node to node only a cylinder pad "
                "of the same radius; for other pairs use a flat specimen or shape = 'nurbs'"
            )
        if len(pad_face) == len(arcs):
            arcs = [_point_image(s.curve, arc, r) for s, arc in zip(pad_face, arcs, strict=True)]
        return _arc_specimen_face(arcs)

    def boundary(self, pad_face: list[Segment], zone: float) -> Boundary:
        """Bottom, sides and the arc face, the pad's face mirrored about y = 0."""
        return _arc_specimen_boundary(self.face(pad_face, zone), self.width / 2, self.height)


@attrs.frozen
class GrooveSpecimen:
    """A specimen whose face is a concave circular arc of radius R (a groove), lowest point
    at the origin, its centre at (0, R): a cylinder pad of a smaller radius sits in it
    (conforming contact, 1/R* = 1/R_pad - 1/R). The face does not mirror the pad's, so it
    pairs with it by projection (``pairing = "node-to-segment"``).

    Attributes
    ----------
    radius, width, height : float
        R (larger than the pad's), width w and height h (bottom at y = -h), mm.
    """

    radius: float = attrs.field(converter=_length("the groove's radius R"))
    width: float = attrs.field(converter=_length("the width w"))
    height: float = attrs.field(converter=_length("the height h"))
    kind = "groove"

    def __attrs_post_init__(self) -> None:
        if self.width / 2 >= self.radius:
            raise ShapeError(
                f"a groove of radius {self.radius:g} mm cannot be {self.width:g} mm wide (the "
                "face would pass the arc's quarter point); make width < 2 radius"
            )

    @property
    def curvature(self) -> float:
        """-1/R: the face is concave at the first contact point (for Hertz)."""
        return -1.0 / self.radius

    def height_at(self, x: np.ndarray) -> np.ndarray:
        """The face's height y(x) above the origin (mm), |x| < R."""
        x = np.asarray(x, float)
        return self.radius - np.sqrt(self.radius**2 - x * x)

    def check_pad(self, face: Sequence[Segment]) -> None:
        """Refuse a pad face that cuts into the groove as drawn (a face flatter than the
        groove over part of its width touches it off its lowest point, e.g. a flat)."""
        half = self.width / 2
        points = np.concatenate([s.curve.points(np.linspace(0.0, 1.0, 65)) for s in face])
        points = points[np.abs(points[:, 0]) < half]
        if not len(points):
            return
        gap = points[:, 1] - self.height_at(points[:, 0])
        worst = int(np.argmin(gap))
        if gap[worst] < -1e-9 * self.radius:
            raise ShapeError(
                f"the pad's face cuts into the groove (radius {self.radius:g} mm) by "
                f"{-gap[worst]:.3g} mm at x = {points[worst, 0]:.4g} mm as drawn: a groove takes "
                "a pad whose face is more curved than its own, lowest at the origin (a cylinder "
                "of a smaller radius); redraw the pad's face or enlarge [specimen] radius"
            )

    def face(self, pad_face: Sequence[Segment], zone: float) -> list[Segment]:
        """The concave face right to left (flank, contact, flank), the contact segment over
        the x range of the ``contact`` segments of ``pad_face``; what :meth:`boundary`
        checks, without building the closed boundary."""
        half, r = self.width / 2, self.radius
        _check_zone(zone, half, "specimen")
        contact = [s.curve for s in pad_face if s.tag == "contact"]
        ends = [contact[0].points([0.0])[0][0], contact[-1].points([1.0])[0][0]]
        if not -half < min(ends) < max(ends) < half:
            raise ShapeError(
                f"the contact zone (x from {min(ends):.4g} to {max(ends):.4g} mm) must lie "
                f"inside the groove (half-width {half:g} mm); widen [specimen] width"
            )
        down = -math.pi / 2
        angles = [down + math.asin(x / r) for x in (half, max(ends), min(ends), -half)]
        return _arc_specimen_face(_arcs([0.0, r], r, angles))

    def boundary(self, pad_face: list[Segment], zone: float) -> Boundary:
        """Bottom, sides and the concave face; the contact segment spans the x range of
        the ``contact`` segments of ``pad_face`` (the pad's zone, or a sliding track)."""
        return _arc_specimen_boundary(self.face(pad_face, zone), self.width / 2, self.height)


@attrs.frozen(eq=False)
class NurbsShape:
    """A body given segment by segment (for anything the library does not draw).

    Attributes
    ----------
    segments : tuple of Segment
        A closed CCW chain; tags as the library's ("contact", "top" for a pad's block,
        "bottom" / "end_left" / "end_right" for a specimen's supports).
    """

    segments: tuple[Segment, ...] = attrs.field(converter=tuple)
    kind = "nurbs"

    @property
    def curvature(self) -> float | None:
        """Unknown: no Hertz reference for a user shape."""
        return None

    def face(self, zone: float | None = None) -> list[Segment]:
        """A pad's face: the segments tagged ``flank_left``, ``contact`` or ``flank_right``,
        in their order (a library specimen facing it mirrors these)."""
        face = [s for s in self.segments if s.tag in ("flank_left", "contact", "flank_right")]
        if not any(s.tag == "contact" for s in face):
            raise ShapeError(
                f"a 'nurbs' body needs a segment tagged 'contact' (the face that touches); its "
                f"tags are {sorted({s.tag for s in self.segments})}: tag the contact segment"
            )
        return face

    @property
    def width(self) -> float:
        """Extent in x of the given segments (the flanks are graded over it)."""
        x = np.concatenate([s.curve.points(np.linspace(0.0, 1.0, 33))[:, 0] for s in self.segments])
        return float(x.max() - x.min())

    def boundary(self, *args) -> Boundary:
        """The closed boundary of the given segments (with a 'contact' segment)."""
        self.face()
        return Boundary(self.segments)
