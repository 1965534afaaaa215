"""Knot vectors, exact NURBS curves and tagged boundaries, with real numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from fretbem.geometry import knots as kv
from fretbem.geometry.boundary import Boundary, BoundaryError, Segment
from fretbem.geometry.nurbs import NurbsCurve, bspline_basis

#: a general rational cubic: non-uniform interior knots, one of them double, uneven weights
CUBIC = NurbsCurve(
    3,
    [0, 0, 0, 0, 0.2, 0.45, 0.45, 0.8, 1, 1, 1, 1],
    [[0, 0], [1, 2], [2.5, 1.5], [3, -1], [4.5, 0.5], [5, 2], [6.5, 1], [7, 0]],
    [1.0, 0.7, 1.8, 1.0, 0.4, 2.5, 1.1, 1.0],
)
#: parameters away from every knot, for finite differences
SMOOTH_XI = np.array([0.05, 0.13, 0.31, 0.39, 0.52, 0.66, 0.74, 0.91, 0.97])


def homogeneous(curve: NurbsCurve) -> np.ndarray:
    """Weighted control points Pw = (w x, w y, w)."""
    return np.column_stack([curve.control_points * curve.weights[:, None], curve.weights])


def curve_size(curve: NurbsCurve) -> float:
    """Largest extent of the control polygon."""
    return float(np.ptp(curve.control_points, axis=0).max())


# --------------------------------------------------------------------------- knot vectors


def test_open_uniform_and_breakpoints():
    """open_uniform(2, 4) is [0 0 0 .25 .5 .75 1 1 1], its breakpoints the 5 element ends."""
    knots = kv.open_uniform(2, 4)
    np.testing.assert_array_equal(knots, [0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1])
    np.testing.assert_array_equal(kv.breakpoints(knots), [0, 0.25, 0.5, 0.75, 1])
    kv.check(knots, 2, 6)


def test_greville_abscissae():
    """Greville points of [0 0 0 .5 1 1 1] are 0, .25, .75, 1 (averages of 2 knots)."""
    np.testing.assert_allclose(kv.greville([0, 0, 0, 0.5, 1, 1, 1], 2), [0, 0.25, 0.75, 1])


def test_elevate_raises_every_multiplicity():
    """Degree elevation adds each distinct knot once."""
    np.testing.assert_array_equal(kv.elevate([0, 0, 0.5, 1, 1]), [0, 0, 0, 0.5, 0.5, 1, 1, 1])


@pytest.mark.parametrize(
    ("degree", "knots", "n", "match"),
    [
        (2, [0, 0, 0, 0.6, 0.4, 1, 1, 1], 5, r"non-decreasing, but knot 4 \(0\.4\) < knot 3"),
        (2, [0, 0, 0, 0.5, 1, 1, 1], 5, r"has 7 entries but degree 2 with 5 .* = 8"),
        (2, [0, 0, 0.2, 0.5, 0.8, 1, 1, 1], 5, r"must be open \(first and last knots repeated"),
        (2, [0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1], 6, r"interior knot 0\.5 is repeated more than"),
        (0, [0, 1], 2, r"degree must be an integer >= 1, got 0"),
        (2, [0, 0, 0, np.nan, 1, 1, 1], 4, r"1-D array of finite numbers"),
        (1, [1, 1, 1, 1], 2, r"empty parameter interval"),
    ],
    ids=["decreasing", "wrong-length", "not-open", "multiplicity", "degree-0", "nan", "empty"],
)
def test_knot_vector_errors(degree, knots, n, match):
    """kv.check rejects each kind of bad knot vector with a message saying what is wrong."""
    with pytest.raises(kv.KnotVectorError, match=match):
        kv.check(np.asarray(knots, float), degree, n)


def test_curve_rejects_bad_knots():
    """NurbsCurve runs the knot check: a decreasing vector is a KnotVectorError (ValueError)."""
    with pytest.raises(ValueError, match="non-decreasing"):
        NurbsCurve(2, [0, 0, 0, 0.7, 0.3, 1, 1, 1], np.zeros((5, 2)), np.ones(5))
    with pytest.raises(kv.KnotVectorError, match=r"degree must be an integer >= 1"):
        NurbsCurve(0, [0, 0.5, 1], [[0, 0], [1, 0]], [1, 1])


@pytest.mark.parametrize(("weight", "shown"), [(0.0, "0.0"), (-0.5, "-0.5")])
def test_curve_rejects_non_positive_weight(weight, shown):
    """A zero or negative weight is refused, naming the weight and its value."""
    with pytest.raises(ValueError, match=rf"NURBS weight 1 is {shown}; weights must be > 0"):
        NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]], [1.0, weight, 1.0])


def test_curve_rejects_nan_control_point():
    """A NaN control point is refused by the finiteness validator, naming the field."""
    with pytest.raises(ValueError, match=r"NurbsCurve\.control_points must be finite"):
        NurbsCurve(1, [0, 0, 1, 1], [[0, 0], [np.nan, 1]], [1, 1])


def test_curve_rejects_weight_count():
    """One weight per control point."""
    with pytest.raises(ValueError, match="3 control points but 2 weights"):
        NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]], [1.0, 1.0])


# --------------------------------------------------------------------------- exact circles


@pytest.mark.parametrize(
    ("center", "radius", "start", "end"),
    [
        ((0.0, 0.0), 1.0, 0.0, 2 * math.pi),
        ((1.5, -0.5), 2.0, 0.3, 0.3 + 2 * math.pi),
        ((0.0, 0.0), 1.0, 0.0, math.pi / 2),
        ((-3.0, 4.0), 0.25, 1.0, 1.0 + 2 * math.pi / 3),
    ],
    ids=["unit-circle", "offset-circle", "quarter", "arc-120"],
)
def test_arc_is_exact_with_radial_normals(center, radius, start, end):
    """Radius error < 1e-14 at 1000 points; unit normals are radial, outward on a CCW arc."""
    curve = NurbsCurve.arc(center, radius, start, end)
    xi = np.linspace(*curve.domain, 1000)
    offset = curve.points(xi) - np.asarray(center)
    r = np.linalg.norm(offset, axis=1)
    assert np.abs(r - radius).max() < 1e-14
    np.testing.assert_allclose(curve.normals(xi), offset / r[:, None], rtol=0, atol=1e-14)
    # end points at the requested angles
    np.testing.assert_allclose(
        curve.points([0.0, 1.0]) - center,
        radius * np.array([[math.cos(start), math.sin(start)], [math.cos(end), math.sin(end)]]),
        atol=1e-14,
    )


def test_clockwise_arc_normals_point_inward():
    """Travelling clockwise, the right-hand normal points to the centre."""
    curve = NurbsCurve.arc([0.0, 0.0], 3.0, math.pi / 2, 0.0)
    xi = np.linspace(0, 1, 101)
    points = curve.points(xi)
    np.testing.assert_allclose(curve.normals(xi), -points / 3.0, atol=1e-14)


def test_arc_length_of_quarter_circle():
    """The integral of |dC/dxi| over a quarter circle of radius 2 is pi, to 1e-13."""
    curve = NurbsCurve.arc([0.0, 0.0], 2.0, 0.0, math.pi / 2)
    x, w = np.polynomial.legendre.leggauss(40)
    length = 0.5 * np.sum(w * curve.jacobians(0.5 * (x + 1)))
    assert length == pytest.approx(math.pi, rel=1e-13)


@pytest.mark.parametrize(("radius", "sweep"), [(0.0, 1.0), (-1.0, 1.0), (1.0, 0.0), (1.0, 7.0)])
def test_arc_rejects_bad_radius_or_sweep(radius, sweep):
    """Radius <= 0, zero sweep and more than a full turn are refused."""
    with pytest.raises(ValueError, match=r"arc (radius|sweep) must"):
        NurbsCurve.arc([0, 0], radius, 0.0, sweep)


# --------------------------------------------------------------------------- basis functions


def test_basis_partition_of_unity_and_reproduction():
    """Rational functions sum to 1 (derivatives to 0) and reproduce the curve: sum R_i P_i."""
    xi = np.linspace(0, 1, 501)
    values, derivatives = CUBIC.basis_functions(xi)
    assert values.shape == (501, CUBIC.n_control_points)
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(derivatives.sum(axis=1), 0.0, atol=1e-12)
    assert values.min() >= 0.0
    np.testing.assert_allclose(values @ CUBIC.control_points, CUBIC.points(xi), atol=1e-13)
    np.testing.assert_allclose(
        derivatives @ CUBIC.control_points, CUBIC.derivatives(xi), atol=1e-11
    )


def test_bspline_basis_matches_local_support():
    """bspline_basis returns p + 1 values per point starting at span - p, summing to 1."""
    knots = kv.open_uniform(3, 5)
    xi = np.array([0.0, 0.1, 0.2, 0.55, 0.999, 1.0])
    values, derivatives, first = bspline_basis(knots, 3, xi)
    assert values.shape == derivatives.shape == (6, 4)
    np.testing.assert_array_equal(first, [0, 0, 1, 2, 4, 4])
    np.testing.assert_allclose(values.sum(axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(derivatives.sum(axis=1), 0.0, atol=1e-12)


def test_derivatives_match_finite_differences():
    """dC/dxi and dR/dxi agree with 4th-order central differences (step 1e-4) to 1e-9."""
    h = 1e-4

    def fd(f):
        return (f(SMOOTH_XI - 2 * h) - 8 * f(SMOOTH_XI - h) + 8 * f(SMOOTH_XI + h)
                - f(SMOOTH_XI + 2 * h)) / (12 * h)  # fmt: skip

    # derivatives reach ~17; measured differences ~1.2e-11, so 1e-9 leaves a 100x margin
    np.testing.assert_allclose(CUBIC.derivatives(SMOOTH_XI), fd(CUBIC.points), rtol=0, atol=1e-9)
    _, d_basis = CUBIC.basis_functions(SMOOTH_XI)
    np.testing.assert_allclose(
        d_basis, fd(lambda xi: CUBIC.basis_functions(xi)[0]), rtol=0, atol=1e-9
    )


@pytest.mark.parametrize("shape", [(), (7,), (3, 4)])
def test_points_and_derivatives_equal_the_two_calls_bit_for_bit(shape):
    """One basis evaluation for both (the Newton steps of the face inverses) gives exactly
    what points() and derivatives() give, in their shapes."""
    arc = NurbsCurve.arc([0.0, 0.0], 70.0, 1.2, 1.9)
    for curve in (CUBIC, arc):
        xi = np.random.default_rng(3).uniform(0.0, 1.0, size=shape)
        point, derivative = curve.points_and_derivatives(xi)
        np.testing.assert_array_equal(point, curve.points(xi))
        np.testing.assert_array_equal(derivative, curve.derivatives(xi))
        assert point.shape == derivative.shape == (*shape, 2)


# --------------------------------------------------------------------------- refinement


def test_knot_insertion_keeps_curve_and_returns_transform():
    """Inserting 3 knots adds 3 control points, moves the curve < 1e-13, Pw_new = T @ Pw_old."""
    refined, transform = CUBIC.insert_knots([0.1, 0.45, 0.6])
    assert refined.n_control_points == CUBIC.n_control_points + 3
    assert transform.shape == (refined.n_control_points, CUBIC.n_control_points)
    xi = np.linspace(0, 1, 1001)
    assert np.abs(refined.points(xi) - CUBIC.points(xi)).max() < 1e-13 * curve_size(CUBIC)
    np.testing.assert_allclose(homogeneous(refined), transform @ homogeneous(CUBIC), atol=1e-13)
    np.testing.assert_allclose(transform.sum(axis=1), 1.0, atol=1e-13)  # convex combinations


def test_degree_elevation_keeps_curve_and_returns_transform():
    """Raising degree 3 -> 5 keeps the curve to < 1e-13 and Pw_new = T @ Pw_old."""
    refined, transform = CUBIC.elevate_degree(2)
    assert refined.degree == 5
    # every distinct knot gains 2: 4 distinct values (0, .2, .45, .8, 1 -> 5) x 2 = 10 more
    assert refined.knots.size == CUBIC.knots.size + 10
    xi = np.linspace(0, 1, 1001)
    assert np.abs(refined.points(xi) - CUBIC.points(xi)).max() < 1e-13 * curve_size(CUBIC)
    np.testing.assert_allclose(homogeneous(refined), transform @ homogeneous(CUBIC), atol=1e-12)


def test_elevated_circle_stays_exact():
    """A quarter circle elevated to degree 4 with 5 knots inserted is still exact (< 1e-14)."""
    curve, _ = NurbsCurve.arc([0, 0], 1.0, 0, math.pi / 2).elevate_degree(2)
    curve, _ = curve.insert_knots([0.1, 0.3, 0.5, 0.7, 0.9])
    xi = np.linspace(0, 1, 1000)
    assert np.abs(np.linalg.norm(curve.points(xi), axis=1) - 1.0).max() < 1e-14


def test_insertion_outside_domain_is_refused():
    """Knots on or beyond the ends of the domain are errors."""
    with pytest.raises(ValueError, match=r"strictly inside the domain \(0\.0, 1\.0\)"):
        CUBIC.insert_knots([0.0])
    with pytest.raises(ValueError, match=r"strictly inside the domain"):
        CUBIC.insert_knots([0.5, 1.2])


def test_refine_refuses_a_space_not_containing_the_curve():
    """refine() onto knots lacking the curve's double knot at 0.45 must raise, not move it."""
    with pytest.raises(ValueError, match="do not contain the curve's spline space"):
        CUBIC.refine(kv.open_uniform(3, 5))


def test_reversed_and_reparametrised():
    """Reversal flips travel direction and normals; reparametrising keeps the points."""
    xi = np.linspace(0, 1, 51)
    back = CUBIC.reversed()
    np.testing.assert_allclose(back.points(1 - xi), CUBIC.points(xi), atol=1e-14)
    np.testing.assert_allclose(back.normals(1 - xi[1:-1]), -CUBIC.normals(xi[1:-1]), atol=1e-12)
    moved = CUBIC.reparametrised((2.0, 6.0))
    assert moved.domain == (2.0, 6.0)
    np.testing.assert_allclose(moved.points(2 + 4 * xi), CUBIC.points(xi), atol=1e-14)


@st.composite
def open_curves(draw) -> NurbsCurve:
    """Random valid NURBS: degree 1-4, open knots, interior multiplicity <= p, weights > 0."""
    degree = draw(st.integers(1, 4))
    # distinct knots on a 1/100 grid: knots one ulp apart are valid but degenerate (see
    # test_random_knot_insertion_keeps_curve)
    values = draw(st.lists(st.integers(1, 99), max_size=5, unique=True).map(sorted))
    values = [v / 100 for v in values]
    multiplicities = [draw(st.integers(1, degree)) for _ in values]
    interior = np.repeat(values, multiplicities)
    knots = np.concatenate([np.zeros(degree + 1), interior, np.ones(degree + 1)])
    n = knots.size - degree - 1
    coordinate = st.floats(-10.0, 10.0, allow_nan=False)
    points = draw(st.lists(st.tuples(coordinate, coordinate), min_size=n, max_size=n))
    weights = draw(st.lists(st.floats(0.2, 5.0), min_size=n, max_size=n))
    return NurbsCurve(degree, knots, points, weights)


def assert_same_curve(refined: NurbsCurve, curve: NurbsCurve, transform: np.ndarray) -> None:
    """Curves agree to 1e-10 of the control polygon size, and Pw_new = T @ Pw_old."""
    scale = max(curve_size(curve), 1e-3)
    xi = np.linspace(0, 1, 257)
    assert np.abs(refined.points(xi) - curve.points(xi)).max() <= 1e-10 * scale
    pw_scale = np.abs(homogeneous(curve)).max()
    assert np.abs(homogeneous(refined) - transform @ homogeneous(curve)).max() <= 1e-10 * pw_scale


@settings(max_examples=60, deadline=None)
@given(curve=open_curves(), data=st.data())
def test_random_knot_insertion_keeps_curve(curve, data):
    """Any valid curve is unchanged by inserting random knots, new or raising a multiplicity."""
    new = data.draw(st.lists(st.floats(0.001, 0.999), min_size=1, max_size=4, unique=True))
    # keep new knots 1e-9 away from the others: Greville interpolation, which refine() uses,
    # needs distinct sites, and knots an ulp apart make two sites coincide
    kept: list[float] = []
    for v in new:
        if np.abs(np.concatenate([curve.knots, kept]) - v).min() > 1e-9:
            kept.append(v)
    new = kept
    values, counts = np.unique(curve.knots[curve.degree + 1 : -curve.degree - 1],
                               return_counts=True)  # fmt: skip
    raisable = values[counts < curve.degree].tolist()
    if raisable and data.draw(st.booleans()):
        new.append(data.draw(st.sampled_from(raisable)))
    assume(new)
    refined, transform = curve.insert_knots(new)
    assert refined.n_control_points == curve.n_control_points + len(new)
    assert_same_curve(refined, curve, transform)


@settings(max_examples=40, deadline=None)
@given(curve=open_curves(), times=st.integers(1, 2))
def test_random_degree_elevation_keeps_curve(curve, times):
    """Any valid curve is unchanged by raising its degree once or twice."""
    refined, transform = curve.elevate_degree(times)
    assert refined.degree == curve.degree + times
    assert_same_curve(refined, curve, transform)


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_insertion_operator_is_the_greville_interpolation(degree, seed):
    """Knot insertion's operator (the Oslo algorithm) is the one interpolation at the new
    Greville abscissae gives (measured 1e-15; asked 1e-13), on curves with repeated interior
    knots and 60 knots added (some raising a multiplicity), and keeps the curve to round-off
    (measured 7e-16 of the control polygon; asked 1e-14)."""
    rng = np.random.default_rng(seed)
    interior = np.sort(rng.uniform(0.05, 0.95, 4))
    interior = np.sort(np.concatenate([interior, np.repeat(interior[1], degree - 1)]))
    old = np.concatenate([np.zeros(degree + 1), interior, np.ones(degree + 1)])
    n = old.size - degree - 1
    curve = NurbsCurve(degree, old, rng.normal(size=(n, 2)), rng.uniform(0.3, 3.0, n))
    raised = interior[-1:] if degree > 1 else interior[:0]  # a simple knot made double
    added = np.concatenate([np.linspace(0.0, 1.0, 61)[1:-1], raised])
    refined, transform = curve.refine(kv.insert(old, added))
    sites = kv.greville(refined.knots, degree)

    def collocation(knots):
        values, _, first = bspline_basis(knots, degree, sites)
        dense = np.zeros((sites.size, knots.size - degree - 1))
        dense[np.arange(sites.size)[:, None], first[:, None] + np.arange(degree + 1)] = values
        return dense

    expected = np.linalg.solve(collocation(refined.knots), collocation(old))
    assert np.abs(transform - expected).max() < 1e-13
    xi = np.linspace(0, 1, 1001)
    assert np.abs(refined.points(xi) - curve.points(xi)).max() < 1e-14 * curve_size(curve)
    np.testing.assert_allclose(transform.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    assert transform.min() >= 0.0  # convex rows: the new weights stay positive


def test_insertion_takes_knots_an_ulp_apart():
    """Knot insertion needs no distinct interpolation sites: a knot an ulp from another is
    inserted exactly (the interpolation could not, its sites coinciding)."""
    refined, _ = CUBIC.insert_knots([0.3, np.nextafter(0.3, 1.0)])
    xi = np.linspace(0, 1, 257)
    assert np.abs(refined.points(xi) - CUBIC.points(xi)).max() < 1e-14 * curve_size(CUBIC)


# --------------------------------------------------------------------------- boundaries

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


def test_polygon_tags_and_indices():
    """Segments keep their tags in order; a shared tag maps to every segment carrying it."""
    boundary = Boundary.polygon([[0, 0], [2, 0], [2, 1], [1, 1.5], [0, 1]],
                                ["bottom", "side", "top", "top", "side"])  # fmt: skip
    assert boundary.tags == ("bottom", "side", "top", "top", "side")
    assert boundary.indices("top") == [2, 3]
    assert boundary.indices("side") == [1, 4]
    np.testing.assert_allclose(boundary.segments[0].curve.normals([0.5]), [[0.0, -1.0]])


def test_unknown_tag_lists_the_tags():
    """Asking for a tag no segment has is a KeyError listing the tags that exist."""
    boundary = Boundary.polygon(SQUARE, ["bottom", "right", "top", "left"])
    with pytest.raises(KeyError, match=r"no boundary segment is tagged 'roof'; the tags are "
                       r"\['bottom', 'left', 'right', 'top'\]"):  # fmt: skip
        boundary.indices("roof")


def test_segment_reparametrises_onto_unit_interval():
    """A Segment's curve always runs over [0, 1], and the tag must be a string."""
    segment = Segment("arc", NurbsCurve.arc([0, 0], 1.0, 0, 1.0).reparametrised((3.0, 5.0)))
    assert segment.curve.domain == (0.0, 1.0)
    with pytest.raises(TypeError, match="tag"):
        Segment(3, NurbsCurve.line([0, 0], [1, 0]))


def test_boundary_not_closed():
    """A gap between consecutive segments is reported with the segments involved."""
    segments = [
        Segment("a", NurbsCurve.line([0, 0], [1, 0])),
        Segment("b", NurbsCurve.line([1, 0], [1, 1])),
        Segment("c", NurbsCurve.line([1, 1], [0, 0.1])),
    ]
    with pytest.raises(BoundaryError, match=r"not closed: segment 2 \('c'\) .*\(gap 0\.1\)"):
        Boundary(segments)


def test_boundary_self_crossing():
    """A figure-eight (bow-tie) polygon crosses itself."""
    with pytest.raises(BoundaryError, match=r"crosses itself: segments 0 \('a'\) and 2 \('c'\)"):
        Boundary.polygon([[0, 0], [1, 1], [1, 0], [0, 1]], ["a", "b", "c", "d"])


def test_boundary_clockwise_and_reversed():
    """A clockwise boundary is refused with a hint; reversed() of a valid one is clockwise."""
    with pytest.raises(BoundaryError, match=r"runs clockwise .* Boundary\.reversed\(\)"):
        Boundary.polygon(SQUARE[::-1], ["a", "b", "c", "d"])
    ccw = Boundary.polygon(SQUARE, ["a", "b", "c", "d"])
    with pytest.raises(BoundaryError, match="clockwise"):
        ccw.reversed()


def test_boundary_with_arcs_is_accepted():
    """A quarter annulus (two lines, two arcs) is closed, simple and counter-clockwise."""
    boundary = Boundary([
        Segment("bottom", NurbsCurve.line([1, 0], [2, 0])),
        Segment("outer", NurbsCurve.arc([0, 0], 2.0, 0, math.pi / 2)),
        Segment("left", NurbsCurve.line([0, 2], [0, 1])),
        Segment("inner", NurbsCurve.arc([0, 0], 1.0, math.pi / 2, 0)),
    ])  # fmt: skip
    assert boundary.tags == ("bottom", "outer", "left", "inner")


def test_polygon_needs_one_tag_per_side():
    """Tag count must match the number of sides."""
    with pytest.raises(ValueError, match="polygon has 4 sides but 3 tags"):
        Boundary.polygon(SQUARE, ["a", "b", "c"])


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_bspline_basis_matches_scipy(degree):
    """The vectorised Cox-de Boor equals scipy's design matrix and BSpline derivative."""
    from scipy.interpolate import BSpline

    from fretbem.geometry.nurbs import bspline_basis

    knots = kv.from_breakpoints(np.array([0.0, 0.1, 0.35, 0.4, 0.8, 1.0]), degree)
    xi = np.concatenate([np.linspace(0, 1, 97), [0.1, 0.35, 1.0]])
    values, derivatives, first = bspline_basis(knots, degree, xi)
    n = knots.size - degree - 1
    dense = np.zeros((2, xi.size, n))
    cols = first[:, None] + np.arange(degree + 1)
    dense[0][np.arange(xi.size)[:, None], cols] = values
    dense[1][np.arange(xi.size)[:, None], cols] = derivatives
    np.testing.assert_allclose(
        dense[0], BSpline.design_matrix(xi, knots, degree).toarray(), atol=1e-14
    )
    np.testing.assert_allclose(dense[1], BSpline(knots, np.eye(n), degree)(xi, nu=1), atol=1e-11)


@pytest.mark.parametrize("seed", range(5))
def test_candidate_pairs_equal_the_exhaustive_box_overlaps(seed):
    """The sort-and-sweep of the self-intersection checks misses no overlapping box pair."""
    from fretbem.geometry.boundary import _candidate_pairs

    rng = np.random.default_rng(seed)
    edges = rng.uniform(0.0, 1.0, (120, 2, 2)) * [1.0, 0.3]
    edges[::7, 1] = edges[::7, 0] + [0.0, 0.2]  # some vertical edges: equal x bounds
    pad = 0.01
    lo, hi = edges.min(axis=1) - pad, edges.max(axis=1) + pad
    n = len(edges)
    expected = [
        (i, j)
        for i in range(n)
        for j in range(i + 2, n)
        if not (i == 0 and j == n - 1) and np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i])
    ]
    i, j = _candidate_pairs(edges, pad)
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == expected


@pytest.mark.parametrize("seed", range(5))
def test_crossings_among_padded_candidates_are_the_unpadded_ones(seed):
    """The boundary's one sweep (padded by the pinch tolerance) finds the first crossing the
    unpadded candidates find: crossing edges have overlapping boxes."""
    from fretbem.geometry.boundary import _candidate_pairs, _crossings

    rng = np.random.default_rng(seed)
    edges = rng.uniform(0.0, 1.0, (80, 2, 2)) * [1.0, 0.3]
    owner = np.arange(len(edges)) // 8
    found = [_crossings(edges, owner, _candidate_pairs(edges, pad)) for pad in (0.0, 1e-9, 0.05)]
    assert found[0] is not None and found[1] == found[0] and found[2] == found[0]


@pytest.mark.parametrize("seed", range(4))
def test_knot_helpers_equal_their_numpy_definitions(seed):
    """breakpoints is np.unique, greville the mean of p consecutive knots (clipped),
    bit for bit: the scene build's faster forms change no geometry."""
    rng = np.random.default_rng(seed)
    for _ in range(200):
        p = int(rng.integers(1, 6))
        inner = np.sort(np.round(rng.uniform(0.0, 1.0, int(rng.integers(0, 30))), 2))
        knots = np.concatenate([[0.0] * (p + 1), inner, [1.0] * (p + 1)]) * 7.3 - 2.1
        n = knots.size - p - 1
        windows = np.lib.stride_tricks.sliding_window_view(knots[1:-1], p)[:n]
        expected = np.clip(windows.mean(axis=1), knots[0], knots[-1])
        assert np.array_equal(kv.greville(knots, p), expected)
        shuffled = rng.permutation(knots)
        assert np.array_equal(kv.breakpoints(shuffled), np.unique(shuffled))


def test_interior_knot_repeated_more_than_degree_is_named():
    """The knot check names the first interior knot repeated more than p times."""
    knots = [0, 0, 0, 0.25, 0.5, 0.5, 0.5, 0.75, 0.75, 0.75, 1, 1, 1]
    with pytest.raises(kv.KnotVectorError, match=r"interior knot 0\.5 is repeated more"):
        kv.check(np.array(knots, float), 2, len(knots) - 3)


def test_shared_refinement_operator_still_checks_each_curve():
    """Curves on one knot vector share the refinement operator, but the check is each
    curve's: a straight polyline fits a space without its knot, a bent one does not."""
    knots, coarser = [0.0, 0.0, 0.5, 1.0, 1.0], [0.0, 0.0, 0.25, 1.0, 1.0]
    straight = NurbsCurve(1, knots, [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]], np.ones(3))
    bent = NurbsCurve(1, knots, [[0.0, 0.0], [0.5, 1.0], [1.0, 0.0]], np.ones(3))
    refined, transform = straight.refine(coarser)
    np.testing.assert_allclose(refined.points(np.linspace(0, 1, 9)),
                               straight.points(np.linspace(0, 1, 9)), atol=1e-14)  # fmt: skip
    transform[0, 0] = 7.0  # the caller's copy: the shared operator is not changed
    with pytest.raises(ValueError, match="do not contain the curve's spline space"):
        bent.refine(coarser)
    again, _ = straight.refine(coarser)
    np.testing.assert_array_equal(again.control_points, refined.control_points)


@pytest.mark.parametrize("sweep", [0.2, 1.0, 3.0, 2 * math.pi, -4.0])
def test_arcs_and_lines_equal_their_checked_construction(sweep):
    """Arcs and lines are built without the field checks (valid by construction): the same
    fields as the checked constructor makes, read-only; a bad input is still named."""
    arc = NurbsCurve.arc([1.5, -70.0], 70.0, 0.3, 0.3 + sweep)
    curves = [arc, *(NurbsCurve.line([0.5, -1.0], [2.0, 3.0], degree=d) for d in (1, 2, 3))]
    for curve in curves:
        checked = NurbsCurve(curve.degree, curve.knots, curve.control_points, curve.weights)
        assert type(curve.degree) is int and curve.degree == checked.degree
        for name in ("knots", "control_points", "weights"):
            got, want = getattr(curve, name), getattr(checked, name)
            assert np.array_equal(got, want) and got.dtype == want.dtype
            assert not got.flags.writeable
    with pytest.raises(ValueError, match="control_points must be finite"):
        NurbsCurve.arc([float("nan"), 0.0], 1.0, 0.0, 1.0)
    infinite = pytest.raises(ValueError, match="control_points must be finite")
    with infinite, np.errstate(all="ignore"):
        NurbsCurve.line([0.0, float("inf")], [1.0, 1.0])
    with pytest.raises(ValueError, match=r"shape \(n, 2\)"):
        NurbsCurve.line([0.0, 0.0, 0.0], [1.0, 1.0, 1.0])


def test_points_are_those_of_points_and_derivatives_bit_for_bit():
    """points() sums the homogeneous point without the derivative, as the joint
    evaluation sums it: the same numbers, at knots and between them, any shape of xi."""
    xi = np.concatenate([SMOOTH_XI, [0.0, 0.2, 0.45, 1.0]])
    for curve in (
        CUBIC,
        NurbsCurve.arc([0.0, 0.0], 2.0, 0.3, 2.9),
        NurbsCurve.line([0, 1], [2, 3]),
    ):
        for values in (xi, xi.reshape(-1, 1), np.array(0.45)):
            np.testing.assert_array_equal(
                curve.points(values), curve.points_and_derivatives(values)[0]
            )


def test_inserted_curve_equals_its_checked_construction():
    """Knot insertion builds the refined curve without the field checks (its knots passed
    the operator's check, its points and weights are convex combinations): the same fields
    as the checked constructor makes, read-only, whether the operator is new or shared."""
    for _ in range(2):  # the second refine takes the kept operator
        refined, _ = CUBIC.refine(kv.insert(CUBIC.knots, np.array([0.1, 0.45, 0.6, 0.6])))
        checked = NurbsCurve(refined.degree, refined.knots, refined.control_points, refined.weights)
        assert type(refined.degree) is int and refined.degree == checked.degree
        for field in ("knots", "control_points", "weights"):
            got, want = getattr(refined, field), getattr(checked, field)
            np.testing.assert_array_equal(got, want)
            assert got.dtype == want.dtype and not got.flags.writeable
