"""Continuous quadratic Lagrange elements, isoparametric, nodes sampled from the NURBS curve."""

from __future__ import annotations

import numpy as np

from fretbem.basis import Basis, Refinement
from fretbem.geometry.nurbs import NurbsCurve


class QuadraticLagrangeBasis(Basis):
    """Conventional BEM family: 3-node elements whose geometry interpolates the exact curve."""

    name = "lagrange2"
    description = "continuous quadratic Lagrange elements, isoparametric (conventional BEM)"
    interpolatory = True

    @classmethod
    def discretise(cls, curve: NurbsCurve, refinement: Refinement) -> QuadraticLagrangeBasis:
        if refinement.degree not in (None, 2):
            raise ValueError(
                f"the lagrange2 family is quadratic only; got degree {refinement.degree} "
                "(use the nurbs family for p-refinement)"
            )
        bounds = refinement.breakpoints()
        n_elements = bounds.size - 1
        params = np.empty(2 * n_elements + 1)
        params[0::2] = bounds
        params[1::2] = 0.5 * (bounds[:-1] + bounds[1:])
        connectivity = 2 * np.arange(n_elements)[:, None] + np.arange(3)
        return cls(
            curve=curve,
            degree=2,
            element_bounds=np.column_stack([bounds[:-1], bounds[1:]]),
            connectivity=connectivity,
            geometry_coefficients=curve.points(params),
            natural_collocation=params,
        )

    def shape_functions(self, elements, local):
        eta = np.asarray(local, float)[:, None]
        values = np.hstack([0.5 * eta * (eta - 1.0), 1.0 - eta**2, 0.5 * eta * (eta + 1.0)])
        derivatives = np.hstack([eta - 0.5, -2.0 * eta, eta + 0.5])
        return values, derivatives
