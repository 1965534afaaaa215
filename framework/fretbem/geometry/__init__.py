"""Geometry: exact NURBS curves and closed boundaries of tagged segments."""
