"""The error tree: every error fretbem raises derives from :class:`FretbemError`.

The branches say what went wrong and how the command line answers (exit codes in
``docs/cli.rst``): bad input (:class:`InputError`, exit 2), a computation that could not be
carried out (:class:`ComputationError`, exit 2), a result that failed its own checks
(:class:`ResultCheckError`, exit 1, nothing written) and an output that cannot be written
(:class:`OutputError`, exit 2). Each branch also derives from the built-in exception it
refines (``ValueError`` or ``RuntimeError``), so ``except ValueError`` keeps working.
"""

from __future__ import annotations

import math

__all__ = [
    "ComputationError",
    "FretbemError",
    "InputError",
    "OutputError",
    "ResourceLimitError",
    "ResultCheckError",
    "SolverSettingsError",
    "StressInputError",
    "UnsupportedError",
]


class FretbemError(Exception):
    """Base of every fretbem error; its message is one line naming the key, cause and fix."""


class InputError(FretbemError, ValueError):
    """An input (scene key, argument, file) is invalid; nothing was computed with it."""


class ComputationError(FretbemError, RuntimeError):
    """A computation could not be carried out (no convergence, a missing component)."""


class ResourceLimitError(ComputationError):
    """The problem would need more memory or time than is available; refused up front."""


class ResultCheckError(FretbemError, RuntimeError):
    """A computed result failed a check; it must not be reported or written as valid.

    Attributes
    ----------
    check : str
        Name of the failed check (the key in summary.json's ``checks``).
    residual : float
        The measured value that failed.
    """

    check = "result"

    def __init__(self, message: str, residual: float = math.nan) -> None:
        super().__init__(message)
        self.residual = float(residual)


class OutputError(FretbemError, RuntimeError):
    """The output directory cannot be used or written; nothing at the target was changed."""


class StressInputError(InputError):
    """A stress request has a bad argument (the message names it and the fix)."""


class UnsupportedError(InputError):
    """A body model does not provide what an output asks of it (the message says what)."""


class SolverSettingsError(InputError):
    """A solver setting (tolerance, iteration counts) outside its meaningful range."""
