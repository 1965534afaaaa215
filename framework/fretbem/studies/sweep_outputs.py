"""Extra per-case output columns: functions named ``"module:function"`` in a sweep.

An output function takes the case's ``SimulationResult`` and its scene dict and returns a
mapping of column name to number or string; the sweep calls it on the worker after each
solved case (so it must be importable there) and an exception in it makes that case an
error row. This is the seam for stress and fatigue columns.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from .sweep_spec import SweepSpecError

OutputFunction = Callable[[Any, Mapping], Mapping[str, Any]]


def resolve(name: str) -> OutputFunction:
    """The function ``"package.module:function"`` names (SweepSpecError if it cannot)."""
    module_name, sep, attribute = str(name).partition(":")
    if not sep or not module_name or not attribute:
        raise SweepSpecError(
            f"an output is named 'package.module:function', got {name!r} "
            "(e.g. 'fretbem.studies.sweep_outputs:reference_errors')"
        )
    try:
        function = getattr(importlib.import_module(module_name), attribute)
    except (ImportError, AttributeError) as err:
        raise SweepSpecError(f"cannot import the output function {name!r}: {err}") from err
    if not callable(function):
        raise SweepSpecError(f"the output {name!r} is not a function")
    return function


def resolve_all(names: Sequence[str]) -> tuple[OutputFunction, ...]:
    """Every named output function, in order."""
    if isinstance(names, str):
        names = [names]
    return tuple(resolve(n) for n in names)


def reference_errors(result, scene: Mapping) -> dict[str, float]:
    """Per step the maximum errors of p and q against the analytical reference (or NaN).

    ``e_p_max.<step>`` and ``e_q_max.<step>`` are normalised by p0 and f p0, as in
    ``fretbem run``'s table; NaN where no closed form applies (dissimilar materials).
    """
    columns = {}
    for step in result.steps:
        errors = step.errors or {}
        for key in ("e_p_max", "e_q_max"):
            columns[f"{key}.{step.name}"] = float(errors.get(key, float("nan")))
    return columns


__all__ = ["OutputFunction", "reference_errors", "resolve", "resolve_all"]
