"""Continuous cubic Lagrange elements, isoparametric, nodes sampled from the NURBS curve."""

from __future__ import annotations

import numpy as np
from numpy.polynomial import polynomial

from fretbem.basis import Basis, Refinement
from fretbem.geometry.nurbs import NurbsCurve

#: the four nodes of the reference element, equally spaced on [-1, 1]
NODES = np.array([-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0])
#: column j holds the power-series coefficients of the Lagrange polynomial of node j
_COEFFICIENTS = np.linalg.inv(polynomial.polyvander(NODES, 3))


class CubicLagrangeBasis(Basis):
    """4-node elements whose geometry interpolates the exact curve at equally spaced nodes."""

    name = "lagrange3"
    description = "continuous cubic Lagrange elements, isoparametric (example plugin)"
    interpolatory = True

    @classmethod
    def discretise(cls, curve: NurbsCurve, refinement: Refinement) -> CubicLagrangeBasis:
        if refinement.degree not in (None, 3):
            raise ValueError(f"the lagrange3 family is cubic only; got degree {refinement.degree}")
        bounds = refinement.breakpoints()
        lo, hi = bounds[:-1, None], bounds[1:, None]
        # element ends and the two inner nodes of each element, in order along the curve
        params = np.append((lo + (NODES[:3] + 1.0) / 2.0 * (hi - lo)).ravel(), 1.0)
        n_elements = bounds.size - 1
        return cls(
            curve=curve,
            degree=3,
            element_bounds=np.column_stack([bounds[:-1], bounds[1:]]),
            connectivity=3 * np.arange(n_elements)[:, None] + np.arange(4),
            geometry_coefficients=curve.points(params),
            natural_collocation=params,
        )

    def shape_functions(self, elements, local):
        eta = np.asarray(local, float)
        values = polynomial.polyvander(eta, 3) @ _COEFFICIENTS
        # d/d(eta) of eta**k is k eta**(k-1)
        derivatives = (polynomial.polyvander(eta, 2) * np.arange(1, 4)) @ _COEFFICIENTS[1:]
        return values, derivatives
