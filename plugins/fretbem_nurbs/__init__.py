"""Isogeometric NURBS basis family for fretbem (registered as ``nurbs``)."""

from .basis import NurbsBasis

__all__ = ["NurbsBasis"]
