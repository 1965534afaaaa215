"""Compatibility for one release: the module paths of the flat layout before the regrouping."""
