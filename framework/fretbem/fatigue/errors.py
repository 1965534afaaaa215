"""The typed errors of the fatigue package: bad input data and missing material constants."""

from __future__ import annotations

from fretbem.errors import InputError

__all__ = ["FatigueInputError", "MissingFatigueDataError"]


class FatigueInputError(InputError):
    """A stress history, request or table entry that the fatigue evaluation cannot use."""


class MissingFatigueDataError(InputError):
    """A life or critical-distance estimate needs a material constant that was not given."""
