"""A cylinder specimen as wide as its pad is the pad's exact point image (two similar
cylinders); a wider one keeps its own flanks."""

from __future__ import annotations

import numpy as np
import pytest

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
