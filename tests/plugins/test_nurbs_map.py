"""The NURBS family's own map and shape functions (one gather of per-element data, columns
over the points) give the generic ``Basis.map`` and ``rational_basis`` numbers bit for bit."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.basis import Basis
from fretbem.geometry.nurbs import rational_basis
from fretbem.testing.conformance import default_curves, default_refinements
from fretbem_nurbs import NurbsBasis
from fretbem_nurbs.basis import _element_table


class _Generic(NurbsBasis):
    """The NURBS family with the generic map over the plain rational basis (the reference)."""

    def shape_functions(self, elements, local):
        elements = np.asarray(elements, dtype=np.intp)
        lo, width, bound, spans = _element_table(self)
        width = width[elements]
        xi = lo[elements] + (np.asarray(local, float) + 1.0) * 0.5 * width
        xi = np.minimum(xi, bound[elements])
        values, derivatives, _ = rational_basis(
            self.curve.knots, self.degree, self.curve.weights, xi, spans[elements]
        )
        return values, derivatives * (0.5 * width)[:, None]

    map = Basis.map


CASES = [
    (name, refinement, degree)
    for name in default_curves()
    for refinement in default_refinements()
    for degree in (None, 4)
]


@pytest.mark.parametrize(("name", "refinement", "degree"), CASES)
def test_map_is_the_generic_map_bit_for_bit(name, refinement, degree):
    curve = default_curves()[name]
    basis = NurbsBasis.discretise(curve, attrs.evolve(refinement, degree=degree))
    reference = _Generic(**{a.name: getattr(basis, a.name) for a in attrs.fields(NurbsBasis)})
    rng = np.random.default_rng(7)
    for size in (0, 1, 5, 400):
        elements = rng.integers(0, basis.n_elements, size)
        local = rng.uniform(-1.0, 1.0, size)
        local[: size // 3] = rng.choice([-1.0, 0.0, 1.0], size // 3)  # ends and middles
        fast, slow = basis.map(elements, local), reference.map(elements, local)
        for field in ("values", "points", "tangents", "jacobians", "normals"):
            got, want = getattr(fast, field), getattr(slow, field)
            assert got.shape == want.shape and got.flags.c_contiguous
            np.testing.assert_array_equal(got, want)
        for got, want in zip(basis.shape_functions(elements, local),
                             reference.shape_functions(elements, local), strict=True):  # fmt: skip
            np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize(("name", "refinement", "degree"), CASES)
def test_abscissae_are_the_maps_first_coordinates_bit_for_bit(name, refinement, degree):
    """The half-plane's x-only evaluation: x, dx/d(local) and the values of the full map
    (its own gather of the coefficients), and the generic Basis.abscissae's."""
    curve = default_curves()[name]
    basis = NurbsBasis.discretise(curve, attrs.evolve(refinement, degree=degree))
    rng = np.random.default_rng(11)
    for size in (0, 1, 5, 400):
        elements = rng.integers(0, basis.n_elements, size)
        local = rng.uniform(-1.0, 1.0, size)
        full = basis.map(elements, local)
        x, dx, values = basis.abscissae(elements, local)
        np.testing.assert_array_equal(x, full.points[:, 0])
        np.testing.assert_array_equal(dx, full.tangents[:, 0])
        np.testing.assert_array_equal(values, full.values)
        for got, want in zip((x, dx, values), Basis.abscissae(basis, elements, local),
                             strict=True):  # fmt: skip
            np.testing.assert_array_equal(got, want)
