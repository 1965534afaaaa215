"""Forget what the BEM assembly keeps between runs, so that a test's next run assembles and
factorises afresh (the paths that keep blocks, images and factors are tested from cold)."""

from __future__ import annotations

from fretbem.bem import assembly, image_factor, image_matrices, images
from fretbem.scenes import builder

__all__ = ["forget_assembled"]


def forget_assembled() -> None:
    """Forget the built scenes, the assembled blocks, the point-image discretisations, the
    kept factorisation and the kept matrices."""
    builder._built.cache_clear()
    assembly.BLOCKS.clear()
    images._DISCRETISED.clear()
    image_factor.clear()
    image_matrices.clear()
