"""Solver algorithms beside the semi-smooth Newton method: Lemke's pivoting on the LCP form."""

from .complementarity import CondensedArrays, LcpIncrement, solve_lcp_increment
from .lemke import LcpSolution, LemkeError, lemke

__all__ = [
    "CondensedArrays",
    "LcpIncrement",
    "LcpSolution",
    "LemkeError",
    "lemke",
    "solve_lcp_increment",
]
