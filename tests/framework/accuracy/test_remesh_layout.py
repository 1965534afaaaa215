"""How many elements an aligned face gets, and how many layouts the re-meshing builds."""

from __future__ import annotations

import numpy as np

from fretbem.accuracy import remesh
from fretbem.basis import face_points
from fretbem.geometry.nurbs import NurbsCurve
from fretbem_lagrange.quadratic import QuadraticLagrangeBasis
from fretbem_nurbs.basis import NurbsBasis

LINE = NurbsCurve.line([0, 0], [1, 0], degree=1)


def fitting(family, degree, pairs, curve, marks, extra=0):
    """Elements chosen and the layouts built, for a face of ``marks`` C0 knots whose build
    counts ``extra`` points more than a line of as many elements would."""
    built = []

    def count_of(elements):
        built.append(elements)
        cost = remesh.c0_cost(family, degree)
        return face_points(family, elements, degree) + cost * marks + extra

    elements = remesh._fitting_elements(family, degree, pairs, curve, lambda n: marks, count_of)
    return elements, built


def loop(family, degree, pairs, marks, extra=0):
    """The layouts one by one, each built: fewer elements by the points in excess."""
    per, _ = remesh.points_per_element(family, degree)
    elements = remesh.elements_for(family, pairs, degree)
    while True:
        points = face_points(family, elements, degree)
        points += remesh.c0_cost(family, degree) * marks + extra
        if points <= pairs or elements <= 1:
            return elements
        elements -= max(1, int(np.ceil((points - pairs) / per)))


def test_an_aligned_face_is_built_once():
    for family, degree in ((NurbsBasis, 2), (NurbsBasis, 3), (QuadraticLagrangeBasis, None)):
        for pairs, marks in ((61, 3), (31, 0), (36, 7), (121, 12)):
            elements, built = fitting(family, degree, pairs, LINE, marks)
            assert built == [elements]
            assert elements == loop(family, degree, pairs, marks)


def test_the_nurbs_face_fits_its_budget_with_one_point_per_knot():
    elements, _ = fitting(NurbsBasis, 2, 61, LINE, 3)
    assert elements == 56  # 58 points of a smooth face, one more per C0 knot
    assert remesh.c0_cost(NurbsBasis, 2) == 1 and remesh.c0_cost(QuadraticLagrangeBasis) == 0


def test_a_count_other_than_foreseen_builds_every_layout():
    """A family (or face) whose count the line does not foresee goes through the builds."""
    elements, built = fitting(NurbsBasis, 2, 61, LINE, 3, extra=2)
    assert elements == loop(NurbsBasis, 2, 61, 3, extra=2)
    # the foreseen layout is built and found off; then every try from the first
    assert built[0] == loop(NurbsBasis, 2, 61, 3)
    assert built[1] == remesh.elements_for(NurbsBasis, 61, 2) and built[-1] == elements


def test_a_face_curve_with_knots_of_its_own_builds_every_layout():
    arc = NurbsCurve.line([0, 0], [1, 0], degree=1).refine(np.array([0.0, 0.0, 0.5, 1.0, 1.0]), 1)
    curve = arc[0] if isinstance(arc, tuple) else arc
    assert curve.knots.size > 4  # an interior knot
    elements, built = fitting(NurbsBasis, 2, 61, curve, 3)
    assert elements == loop(NurbsBasis, 2, 61, 3)
    assert len(built) == 2  # the first try and the one that fits
