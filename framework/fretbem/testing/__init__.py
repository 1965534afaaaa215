"""Conformance checks for the extension points (basis, body, solver) and contact test helpers.

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

__all__ = [
    "FD_TOL",
    "check_basis",
    "check_body",
    "check_solver",
    "default_curves",
    "default_refinements",
]
