"""How many elements an aligned face gets, and how many layouts the re-meshing builds."""

from __future__ import annotations

import numpy as np

from fretbem.accuracy import estimate, remesh
from fretbem.basis import Refinement, face_points
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.testing.scenes import SMALL_SCENE
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


def _toward(sigma):
    """Layouts toward anchors at parameters ``sigma``, marked as the re-meshing marks them
    (the breakpoint nearest each anchor), kept per element count."""
    kept = {}

    def layout(elements):
        if elements not in kept:
            bounds = remesh.aligned_breakpoints(sigma, elements, ratio=20.0, grading=0.06)
            marks = np.unique(
                [t for t in (bounds[np.argmin(np.abs(bounds - s))] for s in sigma) if 0 < t < 1]
            )
            kept[elements] = Refinement.explicit(bounds, degree=2, c0_at=marks)
        return kept[elements]

    return layout, kept


def test_the_marks_are_counted_without_laying_out():
    """Anchors that each stay a breakpoint of their own carry one C0 mark each in every
    layout toward them, so only the layout that fits is built; anchors merged, at a face
    end or coincident are counted by their layouts. The layout chosen is the one every
    layout's own count chooses, for random anchors and budgets."""
    rng = np.random.default_rng(11)
    cost = remesh.c0_cost(NurbsBasis, 2)
    foreseen = 0
    for _ in range(150):
        sigma = rng.uniform(0.0, 1.0, rng.integers(0, 9))
        if sigma.size > 1 and rng.random() < 0.3:  # two anchors merged, or one at an end
            sigma[0] = sigma[1] + 0.5 * remesh.MERGE if rng.random() < 0.5 else 1e-4
        pairs = int(rng.integers(31, 122))
        layout, kept = _toward(sigma)

        def count(elements, layout=layout):
            return face_points(NurbsBasis, elements, 2) + cost * len(layout(elements).c0_at)

        def marks_of(elements, layout=layout):
            return len(layout(elements).c0_at)

        chosen = remesh._fitting_elements(NurbsBasis, 2, pairs, LINE, marks_of, count)
        marks = remesh._marks_count(sigma, centred=False)
        layout, kept = _toward(sigma)
        got = remesh._fitted_layout(NurbsBasis, 2, pairs, LINE, layout, count, marks)
        assert got == layout(chosen)
        if marks is not None:
            foreseen += 1
            assert list(kept) == [chosen]  # no other layout built
            assert marks == len(got.c0_at)
    assert remesh._marks_count(np.array([0.3]), centred=True) is None
    assert 60 < foreseen < 150


def test_the_density_is_compared_near_each_anchor_only():
    """Each anchor's density is compared with the floor only within its reach: the same
    integral, bit for bit, as comparing it over the whole grid, for random anchors, peaks
    (up to 2), ratios (1 to 50) and gradings."""
    rng = np.random.default_rng(5)
    grid = remesh._GRID
    for _ in range(300):
        anchors = np.sort(rng.uniform(0.0, 1.0, rng.integers(1, 10)))
        peaks = rng.choice([1.0, 0.5, 2.0, float(rng.uniform(0.01, 1.0))], anchors.size)
        ratio = float(rng.choice([1.0, 4.0, 20.0, rng.uniform(1.0, 50.0)]))
        grading = float(rng.choice([0.06, 0.15, 1.0, rng.uniform(1e-4, 1.0)]))
        remesh._DENSITIES.clear()
        got = remesh._cumulative_density(anchors, peaks, ratio, grading)
        slope = (ratio - 1.0) / grading
        rho = np.full(grid.size, 1.0 / ratio)
        for anchor, peak in zip(anchors, peaks, strict=True):
            np.maximum(rho, peak / (1.0 + slope * np.abs(grid - anchor)), out=rho)
        want = np.concatenate([[0.0], np.cumsum(0.5 * (rho[1:] + rho[:-1]) * np.diff(grid))])
        assert np.array_equal(got, want)


def test_a_flipped_upper_face_marks_the_anchors_not_their_mirrors(monkeypatch):
    """A face laid out against the pair tangent (its parameter flipped, then flipped back)
    carries its C0 marks at the breakpoints nearest the anchors' own parameters, as an
    unflipped face does, not at their mirror images: asymmetric anchors on the small scene,
    the flip forced (CCW outlines never run the upper face against the tangent)."""

    simulation = build(scene_from_data(SMALL_SCENE))[0]
    anchors = np.array([-0.35, 0.12])
    plain = remesh.remesh(simulation, anchors, 21, independent=False)
    faces = remesh._faces

    def flipped(up_curve, low_curve, tangent):
        return (True, *faces(up_curve, low_curve, tangent)[1:])

    monkeypatch.setattr(remesh, "_faces", flipped)
    turned = remesh.remesh(simulation, anchors, 21, independent=False)
    pair = simulation.pair
    tangent = estimate.pair_frame(pair)[1][0]
    sigma = estimate.parameter_of(pair.upper.face_curve(pair.upper_tag), tangent)(anchors)
    for result in (plain, turned):
        refinement = result.pair.upper.face_refinement(pair.upper_tag)
        bounds, marks = refinement.breakpoints(), np.array(refinement.c0_at)
        nearest = [bounds[np.argmin(np.abs(bounds - t))] for t in sigma]
        assert marks.size == 2 and np.allclose(np.sort(marks), np.sort(nearest))
