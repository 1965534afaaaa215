"""Continuous quadratic Lagrange basis family for fretbem (registered as ``lagrange2``)."""

from .quadratic import QuadraticLagrangeBasis

__all__ = ["QuadraticLagrangeBasis"]
