"""FaceField.closest: the closest points of many points at once, against project."""

from __future__ import annotations

import itertools
import math

import numpy as np

from fretbem import registry
from fretbem.basis import Refinement
from fretbem.contact.faces import FaceField
from fretbem.geometry.nurbs import NurbsCurve

R = 20.0


def _arc_face(parts: int) -> FaceField:
    """A convex arc of radius R (centre (0, -R)) over +-0.3 rad, in ``parts`` segments."""
    family = registry.get("nurbs")
    bounds = np.linspace(0.5 * math.pi - 0.3, 0.5 * math.pi + 0.3, parts + 1)
    segments = tuple(
        family.discretise(
            NurbsCurve.arc([0.0, -R], R, lo, hi).reparametrised((0.0, 1.0)), Refinement(6)
        )
        for lo, hi in itertools.pairwise(bounds)
    )
    sizes = [b.n_functions for b in segments]
    inverses = tuple(np.linalg.inv(b.collocation_matrix()) for b in segments)
    return FaceField(segments, np.concatenate([[0], np.cumsum(sizes)]), inverses)


def test_closest_points_are_on_the_radius_through_each_point():
    """Points above and below a two-segment arc, some by its segments' junction: the
    closest point is where the radius through the point meets the arc (to 1e-12 mm), as
    project finds it, from a start along a tilted tangent too (which puts the points next
    to the junction on the wrong segment first); points past the arc's ends face none."""
    face = _arc_face(2)
    junction = np.array([-2e-3, -5e-4, 5e-4, 2e-3])
    angles = np.concatenate([np.linspace(-0.29, 0.29, 41), junction, [-0.31, 0.35]])
    radii = R + np.resize([0.05, -0.02, 0.3], angles.size)
    points = np.stack([radii * np.sin(angles), radii * np.cos(angles) - R], axis=1)
    inside = np.abs(angles) < 0.3
    expected = np.stack([R * np.sin(angles), R * np.cos(angles) - R], axis=1)[inside]
    for tilt in (0.0, 0.2, -0.2):
        segment, params = face.closest(points, np.array([math.cos(tilt), math.sin(tilt)]))
        assert np.all(segment[~inside] == -1) and np.all(segment[inside] >= 0)
        found = face.points(segment[inside], params[inside])
        assert np.abs(found - expected).max() < 1e-12
    projected = face.points(*face.project(points[inside], np.array([1.0, 0.0])))
    assert np.abs(found - projected).max() < 1e-12
