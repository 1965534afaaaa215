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


def test_the_layout_count_test_answers_as_numpy_sums():
    """The bisection's count test sums in floats and asks numpy only near the target: its
    answer is numpy's (pairwise summation) also at sums a few units of round-off from the
    target, of 1 to 20 gaps, and with a NaN gap."""
    rng = np.random.default_rng(7)
    checked = near = 0
    for _ in range(4000):
        work = rng.random(rng.integers(1, 21)) * 10.0 ** rng.integers(-3, 3)
        h = float(rng.random() + 1e-3)
        exact = float(np.maximum(work / h, 1.0).sum())
        for target in (int(exact), int(exact) + 1, exact, np.nextafter(exact, 0.0)):
            # a float target a rounding away from the sum: the fallback decides
            ulps = abs(exact - target) / np.spacing(exact)
            near += bool(ulps < 2.0)
            expected = bool(np.maximum(work / h, 1.0).sum() > target)
            assert remesh._exceeds(work.tolist(), h, work, target) == expected
            checked += 1
    nan = np.array([1.0, np.nan, 3.0])
    assert remesh._exceeds(nan.tolist(), 0.5, nan, 2) is False
    assert checked == 16000 and near > 4000


def test_aligned_breakpoints_keep_their_density_per_anchor_set():
    """Two element counts toward the same anchors share one density integral; other anchors
    get their own, and the layouts equal those of an emptied store."""
    anchors, peaks = np.array([0.2, 0.45, 0.8]), np.array([1.0, 2.0, 1.0])
    remesh._DENSITIES.clear()
    first = [remesh.aligned_breakpoints(anchors, n, peaks=peaks) for n in (21, 27)]
    assert len(remesh._DENSITIES) == 1
    remesh.aligned_breakpoints(anchors + 0.01, 21, peaks=peaks)
    assert len(remesh._DENSITIES) == 2
    remesh._DENSITIES.clear()
    again = [remesh.aligned_breakpoints(anchors, n, peaks=peaks) for n in (21, 27)]
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
