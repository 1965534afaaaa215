"""fretbem: 2D elastic frictional contact by the boundary element method."""

__version__ = "0.1.0"
