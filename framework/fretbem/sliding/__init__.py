"""Finite sliding: the pairing follows the bodies as they slide many pair spacings.

:func:`~fretbem.sliding.slide.run_sliding` steps a node-to-segment contact through a load
history (a pad driven by displacement can slide in gross slip); the pairs are projected
again whenever the pad has moved more than a pair spacing, and the friction memory is
carried to the new pairing. :func:`~fretbem.sliding.result.solve_sliding` gives the same run
as a :class:`~fretbem.results.SimulationResult` for the writers (``[contact] sliding``).
"""

from .result import solve_sliding, step_solutions
from .slide import SlidingError, SlidingResult, run_sliding

__all__ = ["SlidingError", "SlidingResult", "run_sliding", "solve_sliding", "step_solutions"]
