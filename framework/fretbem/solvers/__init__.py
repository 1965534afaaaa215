"""Solver algorithms beside the semi-smooth Newton method: Lemke's pivoting on the LCP form,
and a solver that falls back to it where Newton fails."""

from .complementarity import CondensedArrays, LcpIncrement, solve_lcp_increment
from .fallback import FallbackSolver
from .lemke import LcpSolution, LemkeError, solve_lcp
from .pivoting import LemkeSolver, PivotingError, UnsupportedLawError

__all__ = [
    "CondensedArrays",
    "FallbackSolver",
    "LcpIncrement",
    "LcpSolution",
    "LemkeError",
    "LemkeSolver",
    "PivotingError",
    "UnsupportedLawError",
    "solve_lcp",
    "solve_lcp_increment",
]
