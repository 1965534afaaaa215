"""Empty the caches a scene build fills, so a timed build is cold as in a fresh process.

Used by the benchmarks that time builds (also against older source trees, which keep fewer
of these caches: a cache the tree does not have is skipped).
"""

from __future__ import annotations

from fretbem import basis
from fretbem.geometry import nurbs
from fretbem.scenes import builder


def clear_scene_caches() -> None:
    """The builder's recent scenes, the graded breakpoints and the refinement operators."""
    for module, name in ((builder, "_built"), (basis, "_graded")):
        cache = getattr(module, name, None)
        if cache is not None:
            cache.cache_clear()
    operators = getattr(nurbs, "_OPERATORS", None)
    if operators is not None:
        operators.clear()
