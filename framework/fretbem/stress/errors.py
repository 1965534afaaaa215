"""Errors raised by the stress evaluation, one type per cause."""

from __future__ import annotations

from fretbem.errors import InputError, StressInputError

__all__ = ["StressInputError", "StressRequestError"]


class StressRequestError(InputError):
    """A ``[stress]`` table or request cannot be read (the message names the key)."""
