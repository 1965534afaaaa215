"""Empty the caches a scene build fills, so a timed build is cold as in a fresh process.

Used by the benchmarks that time builds (also against older source trees, which keep fewer
of these caches: a cache the tree does not have is skipped).
"""

from __future__ import annotations

from fretbem import basis
from fretbem.accuracy import remesh
from fretbem.bem import assembly, body

try:
    from fretbem.bem import mirror
except ImportError:  # an older tree
    mirror = None
try:
    from fretbem.bem import images
except ImportError:  # an older tree
    images = None
try:
    from fretbem.bem import image_factor
except ImportError:  # an older tree
    image_factor = None
try:
    from fretbem.bem import image_matrices
except ImportError:  # an older tree
    image_matrices = None
try:
    from fretbem.halfplane import shared
except ImportError:  # an older tree
    shared = None
from fretbem.geometry import nurbs
from fretbem.scenes import builder


def clear_scene_caches() -> None:
    """The builder's recent scenes and grading ratios, the graded breakpoints, the
    refinement operators, the assembly's block store and the discretisations kept for point
    images (the last cycle's segments, alive until the next cycle's simulation replaces
    theirs, would otherwise lend it their discretisation and rules as point images), and
    the checks and layouts kept by value (the rigid-motion answers, the mirror pair checks,
    the layout densities, the integrated singular rows, the half-plane faces' shared checks
    and force weights, whose last cycle's simulation is still alive while the next one
    builds)."""
    for module, name in ((builder, "_built"), (basis, "_graded"), (builder, "grading_ratio")):
        clear = getattr(getattr(module, name, None), "cache_clear", None)
        if clear is not None:  # (an older tree's grading_ratio keeps nothing)
            clear()
    blocks = getattr(assembly, "BLOCKS", None)
    if blocks is not None:
        blocks.clear()
    discretised = getattr(images, "_DISCRETISED", None)
    if discretised is not None:
        discretised.clear()
    if image_factor is not None:  # the last factorisation, kept for a point image
        image_factor.clear()
    if image_matrices is not None:  # the last body's H and G, kept for a point image
        image_matrices.clear()
    operators = getattr(nurbs, "_OPERATORS", None)
    if operators is not None:
        operators.clear()
    for module, name in (
        (body, "_FREE_MOTIONS"),
        (mirror, "_CHECKED"),
        (remesh, "_DENSITIES"),
        (remesh, "_FACES"),
        (assembly, "_SINGULAR_ON"),
        (shared, "_entries"),
    ):
        cache = getattr(module, name, None)
        if cache is not None:
            cache.clear()
