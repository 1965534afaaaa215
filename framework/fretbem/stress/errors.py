"""Errors raised by the stress evaluation, one type per cause."""

from __future__ import annotations

from fretbem.errors import InputError


class StressInputError(InputError):
    """A stress request has a bad argument (the message names it and the fix)."""


class StressRequestError(InputError):
    """A ``[stress]`` table or request cannot be read (the message names the key)."""
