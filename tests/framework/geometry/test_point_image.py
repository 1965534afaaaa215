"""A cylinder specimen as wide as its pad is the pad's exact point image (two similar
cylinders); a wider one keeps its own flanks."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.geometry.nurbs import NurbsCurve
from fretbem.geometry.shapes import CylinderPad, CylinderSpecimen


def _boundaries(pad_width: float, specimen_width: float, radius: float = 70.0):
    pad = CylinderPad(radius, pad_width, 16.25)
    face = pad.face(1.0)
    specimen = CylinderSpecimen(radius, specimen_width, 16.25)
    return pad.boundary(1.0, face).segments, specimen.boundary(face, 1.0).segments


@pytest.mark.parametrize("radius", [20.0, 70.0, 500.0])
def test_similar_cylinders_are_exact_point_images(radius):
    pad, specimen = _boundaries(6.5, 6.5, radius)
    # specimen segment k is the pad's segment (k - 2) mod 6 reflected through the origin
    for k, segment in enumerate(specimen):
        image = pad[(k - 2) % len(pad)].curve
        assert np.array_equal(segment.curve.control_points, -image.control_points)
        assert np.array_equal(segment.curve.knots, image.knots)
        assert np.array_equal(segment.curve.weights, image.weights)


def test_a_wider_specimen_keeps_its_own_flanks():
    pad, specimen = _boundaries(6.5, 8.0)
    tags = [s.tag for s in specimen]
    contact = specimen[tags.index("contact")].curve
    assert np.array_equal(contact.control_points, -pad[1].curve.control_points)
    flank = specimen[tags.index("flank_right")].curve
    # its own arc out to x = 4 mm, not the pad's flank reflected (which ends at 3.25 mm)
    assert flank.points([0.0])[0, 0] == pytest.approx(4.0, abs=1e-12)
    assert np.hypot(*(flank.points(np.linspace(0, 1, 9)) - [0.0, -70.0]).T) == pytest.approx(70.0)


@pytest.mark.parametrize("width", [6.5, 9.0])
def test_curves_made_without_checks_are_what_the_checked_constructor_makes(width):
    """The faces' reversed, mirrored, symmetrised and point-image curves skip the checks
    (NurbsCurve.exact_image): each is, field by field and bit for bit, read-only, what the
    checked constructor makes of the same arrays."""
    pad, specimen = _boundaries(6.5, width)
    curves = [s.curve for s in (*pad, *specimen)]
    curves += [c.reversed() for c in curves]
    for curve in curves:
        checked = NurbsCurve(curve.degree, curve.knots, curve.control_points, curve.weights)
        assert type(curve.degree) is int and curve.degree == checked.degree
        for name in ("knots", "control_points", "weights"):
            value = getattr(curve, name)
            assert value.dtype == float and value.flags.c_contiguous
            assert not value.flags.writeable
            assert value.tobytes() == getattr(checked, name).tobytes()
