"""Continuous cubic Lagrange basis family for fretbem (registered as ``lagrange3``).

A complete third-party plugin: the family is a :class:`fretbem.basis.Basis` subclass, and
this package's ``pyproject.toml`` declares it under the ``fretbem.bases`` entry-point group.
"""

from .cubic import CubicLagrangeBasis

__all__ = ["CubicLagrangeBasis"]
