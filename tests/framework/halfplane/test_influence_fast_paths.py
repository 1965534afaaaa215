"""The fast paths of the half-plane influence coefficients equal the plain ones.

Newton in a bracket against bisection for the split point, the six-point rule of far
elements against the twelve-point rule everywhere, the banded solve of E^T against the dense
one: on single faces of both families (a line, a flattened arc) and on a joined face.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane import HalfPlaneSurface, influence, surface_integrals
from fretbem.halfplane.joined import JoinedFace
from fretbem.halfplane.surface import transposed_solve
from fretbem.material import Material

STEEL = Material(210000.0, 0.3)


def _bisection(face, elements, targets):
    """Frozen copy of the split-point search before the Newton one: 60 bisections."""
    lo = np.full(len(elements), -1.0)
    hi = np.full(len(elements), 1.0)
    increasing = face.map(elements, hi).points[:, 0] > face.map(elements, lo).points[:, 0]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        move_hi = (face.map(elements, mid).points[:, 0] > targets) == increasing
        hi = np.where(move_hi, mid, hi)
        lo = np.where(move_hi, lo, mid)
    return 0.5 * (lo + hi)


def _arc(elements: int, family: str):
    radius, up = 3.0, math.pi / 2
    phi = math.asin(1.0 / radius)
    curve = NurbsCurve.arc([0.0, -radius], radius, up - phi, up + phi).flattened(0.0)
    return bases.get(family).discretise(curve, Refinement(elements=elements))


def _line(elements: int, family: str, start=-1.0, end=1.0):
    curve = NurbsCurve.line([start, 0.0], [end, 0.0])
    return bases.get(family).discretise(curve, Refinement(elements=elements))


def _joined(family: str):
    ends = [-1.0, -0.3, 0.4, 1.0]
    return JoinedFace([_line(5, family, a, b) for a, b in itertools.pairwise(ends)])


FACES = {
    "line 7": lambda f: _line(7, f),
    "line 40 reversed": lambda f: _line(40, f, 1.0, -1.0),
    "arc 30": lambda f: _arc(30, f),
    "joined 3 x 5": _joined,
}


def _field_points(face) -> np.ndarray:
    elements, local = face.collocation()
    nodes = face.map(elements, local).points[:, 0]
    return np.concatenate([nodes, np.linspace(-1.6, 1.6, 41), [-1.0 - 1e-7, 1.0 + 1e-9]])


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_split_points_equal_bisection(family, name):
    face = FACES[name](family)
    x = _field_points(face)
    elements = np.searchsorted(np.sort(x), x) % face.n_elements  # any elements: miss or hit
    inside = []
    for e in range(face.n_elements):
        ends = face.map(np.array([e, e]), np.array([-1.0, 1.0])).points[:, 0]
        inside.append((e, x[(x > ends.min()) & (x < ends.max())]))
    elements = np.concatenate([np.full(len(xs), e) for e, xs in inside])
    targets = np.concatenate([xs for _, xs in inside])
    assert targets.size > face.n_elements  # every element holds field points
    newton = influence._invert(face, elements, targets)
    np.testing.assert_allclose(newton, _bisection(face, elements, targets), rtol=0, atol=1e-12)


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_far_rule_equals_the_twelve_point_rule(family, name, monkeypatch):
    face = FACES[name](family)
    x = _field_points(face)
    fast = surface_integrals(face, x, 0.7)
    monkeypatch.setattr(influence, "FAR_RATIO", math.inf)  # twelve points on every element
    plain = surface_integrals(face, x, 0.7)
    scale = np.abs(plain.log).max()
    np.testing.assert_allclose(fast.log, plain.log, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(fast.sign, plain.sign, rtol=0, atol=1e-13 * np.abs(plain.sign).max())


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_banded_solve_equals_the_dense_one(family, name):
    surface = HalfPlaneSurface(FACES[name](family), STEEL, "lower", datum=2.0)
    matrix = surface.collocation_matrix
    rows = np.random.default_rng(5).normal(size=(9, matrix.shape[0]))
    np.testing.assert_allclose(
        surface.per_node_value(rows), np.linalg.solve(matrix.T, rows.T).T, rtol=1e-12, atol=1e-12
    )
    # the node map is the coefficient map taken through E^-1
    x = np.linspace(-0.8, 0.8, 5)
    per_coefficient = surface.coefficient_map(x)
    n = matrix.shape[0]
    blocks = np.moveaxis(per_coefficient.reshape(len(x), 2, n, 2), 2, -1).reshape(-1, n)
    dense = np.linalg.solve(matrix.T, blocks.T).T
    dense = np.moveaxis(dense.reshape(len(x), 2, 2, n), -1, 2).reshape(len(x), 2, 2 * n)
    scale = np.abs(dense).max()
    np.testing.assert_allclose(surface.node_map(x), dense, rtol=0, atol=1e-13 * scale)


@pytest.mark.parametrize(("lower", "upper"), [(0, 0), (1, 3), (3, 1), (2, 2), (0, 4)])
def test_transposed_solve_of_any_band(lower, upper):
    """Unequal bands (an E whose nodes lean to one side) and the dense fallback alike."""
    rng = np.random.default_rng(lower + 7 * upper)
    for n in (40, 9):  # banded, then dense (the band is not narrow next to n)
        i, j = np.indices((n, n))
        matrix = np.where((i - j <= lower) & (j - i <= upper), rng.normal(size=(n, n)), 0.0)
        matrix += 4.0 * np.eye(n)
        rows = rng.normal(size=(6, n))
        np.testing.assert_allclose(
            transposed_solve(matrix, rows) @ matrix, rows, rtol=0, atol=1e-12
        )


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_nodes_located_by_their_own_coordinates(family, name, monkeypatch):
    """The face's own nodes given with their (element, local coordinate): no search in
    their own element, the integrals those of the searched split points (to the search's
    resolution), other field points searched as before."""
    face = FACES[name](family)
    x = _field_points(face)
    n = face.n_functions
    elements, local = face.collocation()
    searched_points = []
    invert = influence._invert

    def counted(face, e, targets):
        searched_points.append(e.size)
        return invert(face, e, targets)

    monkeypatch.setattr(influence, "_invert", counted)
    searched = surface_integrals(face, x, 0.7)
    at = (np.concatenate([elements, np.full(x.size - n, -1)]),
          np.concatenate([local, np.zeros(x.size - n)]))  # fmt: skip
    located = surface_integrals(face, x, 0.7, at)
    for got, want in ((located.log, searched.log), (located.sign, searched.sign)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
    assert searched_points[1] <= searched_points[0] - n  # every node's own element skipped


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_one_face_map_serves_the_samples_and_the_integrals(family, name):
    """The rule map (one basis evaluation) gives the Gauss samples and the influence
    integrals each face maps alone, bit for bit: every point is mapped on its own, and x
    and its derivative are summed as the face's map sums them."""
    face = FACES[name](family)
    mapped = influence.rule_map(face)
    alone, shared = influence.gauss_samples(face), influence.gauss_samples(face, mapped)
    for a, b in zip(alone[:2], shared[:2], strict=True):
        assert np.array_equal(a, b)
    for field in ("values", "points", "tangents", "jacobians", "normals"):
        assert np.array_equal(getattr(alone[2], field), getattr(shared[2], field))
    x = _field_points(face)
    own, given = surface_integrals(face, x, 0.7), surface_integrals(face, x, 0.7, mapped=mapped)
    assert np.array_equal(own.log, given.log) and np.array_equal(own.sign, given.sign)


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
def test_element_map_reads_the_faces_map(family, name):
    """The integrals' x-only evaluation (``Basis.abscissae``, a family's own where it has
    one) gives the face map's x, |dx/d(local)| and values bit for bit."""
    face = FACES[name](family)
    elements, local = influence._rule_points(face.n_elements)
    x, jac, values = influence._element_map(face, elements, local)
    full = face.map(elements, local)
    np.testing.assert_array_equal(x, full.points[:, 0])
    np.testing.assert_array_equal(jac, np.abs(full.tangents[:, 0]))
    np.testing.assert_array_equal(values, full.values)


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("name", FACES)
@pytest.mark.parametrize("side", ["lower", "upper"])
def test_nodes_and_rule_points_mapped_in_one_call(family, name, side):
    """A surface that needs its rule map (a lone face, an upper one) maps its nodes in the
    same call: its points, E and rule map those of mapping each alone, bit for bit."""
    face = FACES[name](family)
    surface = HalfPlaneSurface(face, STEEL, side, datum=2.0)
    assert "rule_map" in surface._cache and "points" in surface._cache
    alone = face.map(*face.collocation())
    assert np.array_equal(surface.points, alone.points)
    assert np.array_equal(surface.collocation_matrix, face.collocation_matrix())
    rules = influence.rule_map(face)
    for field in ("values", "points", "tangents", "jacobians", "normals"):
        assert np.array_equal(getattr(surface._rule_map, field), getattr(rules, field))
