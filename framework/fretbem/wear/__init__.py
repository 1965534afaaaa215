"""Fretting wear: wear laws, the worn profile as a gap offset, cycle jumping, results.

A :class:`~fretbem.wear.law.WearLaw` turns the pressure p, the shear q and the slip
increment |ds| of every pair into a wear depth increment of one body. The accumulated depth
of both faces enters the contact as an offset of the initial gap
(:mod:`fretbem.wear.profile`); one simulated load cycle is extrapolated over many cycles
(:mod:`fretbem.wear.jump`, :mod:`fretbem.wear.run`). Theory: docs/explanation/wear.rst.
"""

from .law import ArchardWear, EnergyWear, WearInputError, WearLaw

__all__ = ["ArchardWear", "EnergyWear", "WearInputError", "WearLaw"]
