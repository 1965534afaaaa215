"""Conformance checks for the extension points (basis, body, solver, wear law), test helpers.

The names of :mod:`.conformance` are re-exported here.
"""

from .conformance import (
    FD_TOL,
    check_basis,
    check_body,
    check_solver,
    default_curves,
    default_refinements,
)
from .wear import check_wear_law

__all__ = [
    "FD_TOL",
    "check_basis",
    "check_body",
    "check_solver",
    "check_wear_law",
    "default_curves",
    "default_refinements",
]
