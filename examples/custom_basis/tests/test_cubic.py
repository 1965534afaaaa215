"""The plugin's own tests: the conformance suite every fretbem family passes."""

import numpy as np
from fretbem_cubic import CubicLagrangeBasis

from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.testing.conformance import check_basis


def test_conforms():
    """Partition of unity, derivatives, geometry, E matrix, nodality, nested spaces."""
    check_basis(CubicLagrangeBasis)


def test_reproduces_cubics():
    """A cubic B-spline in one span is reproduced exactly by one cubic element."""
    curve = NurbsCurve(3, [0, 0, 0, 0, 1, 1, 1, 1], [[0, 0], [1, 2], [2, -1], [3, 1]], np.ones(4))
    basis = CubicLagrangeBasis.discretise(curve, Refinement(1))
    xi = np.linspace(0.0, 1.0, 11)
    points = basis.geometry(*basis.to_local(xi))[0]
    assert np.allclose(points, curve.points(xi), atol=1e-12)
