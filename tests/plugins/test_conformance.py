"""Every installed basis family passes fretbem.testing.check_basis;
family-specific checks."""

from __future__ import annotations

import importlib.metadata
import math

import attrs
import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.testing.conformance import check_basis, default_curves
from fretbem_lagrange import QuadraticLagrangeBasis
from fretbem_nurbs import NurbsBasis

FAMILIES = bases.available()
QUARTER = NurbsCurve.arc([0.0, 0.0], 1.0, 0.0, math.pi / 2)


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_family_conforms(family):
    """The family passes the conformance suite (the same helper third parties call)."""
    check_basis(FAMILIES[family])


def test_builtin_families_are_discovered():
    """Both built-in families are found through the registry."""
    assert {"nurbs", "lagrange2"} <= set(FAMILIES)
    assert FAMILIES["nurbs"] is NurbsBasis
    assert FAMILIES["lagrange2"] is QuadraticLagrangeBasis


def test_entry_points_are_declared():
    """The fretbem.bases entry-point group names nurbs and lagrange2 and points at the classes."""
    found = {ep.name: ep for ep in importlib.metadata.entry_points(group="fretbem.bases")}
    assert {"nurbs", "lagrange2"} <= set(found)
    assert found["nurbs"].value == "fretbem_nurbs:NurbsBasis"
    assert found["lagrange2"].value == "fretbem_lagrange:QuadraticLagrangeBasis"
    assert found["nurbs"].load() is NurbsBasis


def test_families_describe_themselves():
    """Each family has a name matching its entry point and a one-line description."""
    for name, cls in FAMILIES.items():
        assert cls.name == name
        assert cls.description and "\n" not in cls.description


# --------------------------------------------------------------------------- exact circle


def _radius_error(basis, local: np.ndarray) -> float:
    """Max | |x| - 1 | of the discretised geometry at ``local`` on every element."""
    elements = np.repeat(np.arange(basis.n_elements), local.size)
    points = basis.geometry(elements, np.tile(local, basis.n_elements))[0]
    return float(np.abs(np.linalg.norm(points, axis=1) - 1.0).max())


@pytest.mark.parametrize("elements", [1, 4, 13])
def test_nurbs_geometry_is_the_exact_circle(elements):
    """The nurbs family carries the circle exactly: radius error < 1e-13 everywhere on an arc."""
    basis = NurbsBasis.discretise(QUARTER, Refinement(elements))
    assert _radius_error(basis, np.linspace(-1, 1, 41)) < 1e-13
    graded = NurbsBasis.discretise(QUARTER, Refinement.graded(elements, 0.0, ratio=4.0))
    assert _radius_error(graded, np.linspace(-1, 1, 41)) < 1e-13


def test_lagrange_geometry_is_not_the_circle():
    """lagrange2 interpolates the circle at its nodes only: > 1e-6 off between them."""
    basis = QuadraticLagrangeBasis.discretise(QUARTER, Refinement(4))
    assert _radius_error(basis, np.array([-1.0, 0.0, 1.0])) < 1e-15  # the nodes
    between = _radius_error(basis, np.array([-0.5, 0.5]))
    assert between > 1e-6
    # and the error is geometric, O(h^4) in the radius, not round-off: about 1e-4 here
    assert 1e-5 < between < 1e-3


# --------------------------------------------------------------------------- degrees


def test_nurbs_p_refinement():
    """Refinement(degree=3) gives cubic NURBS, 4 local functions, still exact and conforming."""
    basis = NurbsBasis.discretise(QUARTER, Refinement(elements=5, degree=3))
    assert basis.degree == 3 and basis.n_local == 4
    assert basis.n_functions == 5 + 3  # open knots, simple interior knots
    assert _radius_error(basis, np.linspace(-1, 1, 21)) < 1e-13
    check_basis(NurbsBasis, refinements=[Refinement(1, 3), Refinement(3, 4), Refinement(4, 3)])


def test_nurbs_lines_get_quadratic_unknowns():
    """A straight line (degree 1) is elevated to the family's default degree 2."""
    basis = NurbsBasis.discretise(NurbsCurve.line([0, 0], [1, 0]), Refinement(3))
    assert basis.degree == 2 and basis.n_functions == 5


def test_nurbs_refuses_to_lower_the_geometry_degree():
    """Degree 1 on a quadratic arc would lose the exact geometry: a clear error."""
    with pytest.raises(ValueError, match=r"cannot lower a segment's degree \(2\) to 1"):
        NurbsBasis.discretise(QUARTER, Refinement(elements=2, degree=1))


def test_lagrange_rejects_degree_3():
    """lagrange2 is quadratic only and says to use nurbs for p-refinement."""
    with pytest.raises(ValueError, match=r"quadratic only; got degree 3 .*use the nurbs family"):
        QuadraticLagrangeBasis.discretise(QUARTER, Refinement(elements=2, degree=3))
    assert QuadraticLagrangeBasis.discretise(QUARTER, Refinement(2, degree=2)).degree == 2


# --------------------------------------------------------------------------- the helper bites


class _WrongDerivative(QuadraticLagrangeBasis):
    """Derivatives off by 0.1 %."""

    def shape_functions(self, elements, local):
        values, derivatives = super().shape_functions(elements, local)
        return values, 1.001 * derivatives


class _NoPartition(QuadraticLagrangeBasis):
    """First local function scaled: the values no longer sum to one."""

    def shape_functions(self, elements, local):
        values, derivatives = super().shape_functions(elements, local)
        return values * np.array([1.001, 1.0, 1.0]), derivatives


class _ClaimsNodal(NurbsBasis):
    """NURBS functions are not nodal, whatever the class says."""

    interpolatory = True


class _LostFunction(QuadraticLagrangeBasis):
    """The last element forgets the segment's last function."""

    @classmethod
    def discretise(cls, curve, refinement):
        basis = super().discretise(curve, refinement)
        connectivity = basis.connectivity.copy()
        connectivity[-1, -1] = connectivity[-1, 0]
        return attrs.evolve(basis, connectivity=connectivity)


class _OffTheCurve(QuadraticLagrangeBasis):
    """Element-end nodes displaced by 1e-6."""

    @classmethod
    def discretise(cls, curve, refinement):
        basis = super().discretise(curve, refinement)
        return attrs.evolve(basis, geometry_coefficients=basis.geometry_coefficients + 1e-6)


class _NotNested(QuadraticLagrangeBasis):
    """One element more than asked: meshes of n + 1 and 2 n + 1 elements do not nest."""

    @classmethod
    def discretise(cls, curve, refinement):
        return super().discretise(curve, attrs.evolve(refinement, elements=refinement.elements + 1))


class _CollocatesAtEnds(QuadraticLagrangeBasis):
    """Collocation left at the segment's end nodes."""

    @property
    def collocation_parameters(self):
        return self.natural_collocation


class _NotOdd(QuadraticLagrangeBasis):
    """Points shifted by 1e-13 (harmless to the geometry checks): the map of a point image is
    no longer the map reflected, which the BEM assembly's reuse of image blocks relies on."""

    def map(self, elements, local):
        element_map = super().map(elements, local)
        return attrs.evolve(element_map, points=element_map.points + 1e-13)


class _DeclaredNotOdd(_NotOdd):
    """The same family, declaring it: no point image is taken, and nothing is checked."""

    odd_in_geometry = False


@pytest.mark.parametrize(
    ("cls", "message"),
    [
        (_WrongDerivative, "derivatives match finite differences"),
        (_NotOdd, r"point image \(odd_in_geometry\).*odd_in_geometry = False"),
        (_NoPartition, r"partition of unity \(sum phi = 1\)"),
        (_ClaimsNodal, "functions are nodal at natural_collocation"),
        (_LostFunction, "connectivity indices cover"),
        (_OffTheCurve, "element ends lie on the exact curve"),
        (_NotNested, "refinement invariance"),
        (_CollocatesAtEnds, "collocation points lie strictly inside"),
    ],
    ids=lambda v: v.__name__.strip("_") if isinstance(v, type) else None,
)
def test_check_basis_detects_broken_families(cls, message):
    """Each deliberately broken family fails check_basis with the property named."""
    with pytest.raises(AssertionError, match=message):
        check_basis(cls)


def test_a_family_that_is_not_odd_in_the_geometry_passes_when_it_says_so():
    """odd_in_geometry = False: the point-image check is skipped (and images are not reused)."""
    check_basis(_DeclaredNotOdd)


def test_check_basis_accepts_custom_curves_and_names_the_case():
    """Curves may be given as a list; the failure message names family, curve and refinement."""
    check_basis(QuadraticLagrangeBasis, curves=[QUARTER.reparametrised((2.0, 3.0))])
    with pytest.raises(AssertionError, match=r"_WrongDerivative \(family 'lagrange2'\) on the "
                       r"line with Refinement\(elements=1"):  # fmt: skip
        check_basis(_WrongDerivative, curves={"line": default_curves()["line"]})
    with pytest.raises(TypeError, match="Basis subclass"):
        check_basis(NurbsCurve)


# ------------------------------------------------------------ short elements, far from 0


@pytest.mark.parametrize("family", sorted(FAMILIES))
@pytest.mark.parametrize("c0", [False, True])
def test_short_elements_keep_their_own_functions_at_their_ends(family, c0):
    """An element's functions at its own end (local +1) are its own, however short the
    element and wherever it lies: graded faces put elements of 1e-4 of the parameter near
    parameter 0.9, where nudging the end inside by 1e-13 of the span is below the float's
    resolution. They were the next element's, which made the half-plane and BEM surface
    integrals see elements of zero length and graded faces above about 360 points
    oscillate (50 % of p0)."""
    curve = NurbsCurve.line([0.0, 0.0], [2.0, 0.5])
    fine = 0.9 + np.cumsum(np.full(12, 1e-4))
    bounds = np.unique(np.concatenate([np.linspace(0.0, 0.9, 10), fine, [0.95, 1.0]]))
    marks = [float(fine[5])] if c0 else []
    basis = FAMILIES[family].discretise(curve, Refinement.explicit(bounds, c0_at=marks))
    lo, hi = basis.element_bounds.T
    for local, params in ((-1.0, lo), (1.0, hi)):
        elements = np.arange(basis.n_elements)
        m = basis.map(elements, np.full(elements.size, local))
        assert np.allclose(m.points, curve.points(params), rtol=0.0, atol=1e-12)
        inner = basis.map(elements, np.full(elements.size, local * (1.0 - 1e-9)))
        assert np.allclose(m.values, inner.values, rtol=0.0, atol=1e-6)
        assert np.allclose(m.tangents, inner.tangents, rtol=1e-6, atol=0.0)
