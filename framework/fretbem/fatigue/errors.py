"""The typed errors of the fatigue package: bad input data and missing material constants."""

from __future__ import annotations

__all__ = ["FatigueInputError", "MissingFatigueDataError"]


class FatigueInputError(ValueError):
    """A stress history, request or table entry that the fatigue evaluation cannot use."""


class MissingFatigueDataError(ValueError):
    """A life or critical-distance estimate needs a material constant that was not given."""
