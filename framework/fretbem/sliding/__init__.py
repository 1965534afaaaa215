"""Finite sliding: the pairing follows the bodies as they slide many pair spacings.

:func:`~fretbem.sliding.slide.run_sliding` steps a node-to-segment contact through a
history whose steps also carry the upper body rigidly along the surface; the pairs are
projected again at every increment and the friction memory is carried to the new pairing.
"""

from .slide import SlideStep, SlidingError, SlidingResult, run_sliding

__all__ = ["SlideStep", "SlidingError", "SlidingResult", "run_sliding"]
