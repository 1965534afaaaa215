"""Numerical building blocks shared by every layer: quadrature rules and BLAS threading."""
