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

import numpy as np

from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.fatigue.request import fatigue_request_from_dict
from fretbem.fatigue.run import run_fatigue
from fretbem.stress.evaluate import StressEvaluator

from .spec import SweepSpecError

OutputFunction = Callable[[Any, Mapping], Mapping[str, Any]]


def resolve(name: str) -> OutputFunction:
    """The function ``"package.module:function"`` names (SweepSpecError if it cannot)."""
    module_name, sep, attribute = str(name).partition(":")
    if not sep or not module_name or not attribute:
        raise SweepSpecError(
            f"an output is named 'package.module:function', got {name!r} "
            "(e.g. 'fretbem.studies.sweep.outputs:reference_errors')"
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


#: per process: one stress evaluator per contact pair (its matrix depends on the body and
#: the points only, so every case of a group reuses it)
_EVALUATORS: dict[int, Any] = {}


def _surface_evaluator(result):
    pair = result.simulation.pair
    evaluator = _EVALUATORS.get(id(pair))
    if evaluator is None or evaluator.result.simulation.pair is not pair:
        if len(_EVALUATORS) > 4:
            _EVALUATORS.clear()
        points = np.asarray(pair.pairing().points, dtype=float)
        evaluator = StressEvaluator(result, points, "lower")
        _EVALUATORS[id(pair)] = evaluator
    evaluator.result = result  # same bodies and points: the matrix is reused
    return evaluator


def surface_stress(result, scene: Mapping) -> dict[str, float]:
    """Peak surface sigma_xx of the lower body (specimen) per step and over the cycle, MPa.

    Evaluated at the contact pairs' positions on the lower face by
    :class:`fretbem.stress.evaluate.StressEvaluator` (bulk stress included): columns
    ``sxx_max.<step>`` and ``sxx_max``.
    """
    stress = _surface_evaluator(result).steps()  # (n_steps, n_pairs, 4)
    peaks = stress[:, :, 0].max(axis=1)
    columns = {f"sxx_max.{s.name}": float(v) for s, v in zip(result.steps, peaks, strict=True)}
    columns["sxx_max"] = float(peaks.max())
    return columns


def fatigue(result, scene: Mapping) -> dict[str, Any]:
    """Hot-spot parameter and life per method from the ``[fatigue]`` table.

    The table comes from the sweep file (or from a two-body scene that carries one).

    Runs :func:`fretbem.fatigue.run.run_fatigue` on the lower body's stress history
    (:class:`fretbem.fatigue.from_simulation.SimulationStressHistory`): columns
    ``<method>.parameter``, ``<method>.life`` (cycles, inf for a run-out, NaN with the reason
    in ``<method>.life_note``), ``<method>.x`` and ``<method>.depth`` (hot spot, mm). The
    fatigue evaluation (stress map and plane search) costs far more than the contact solve.
    """
    table = scene.get("fatigue")
    if not isinstance(table, Mapping):
        raise SweepSpecError(
            "the fatigue output needs a [fatigue] table (material, methods...) in the sweep "
            "file or the scene"
        )
    report = run_fatigue(SimulationStressHistory(result), fatigue_request_from_dict(table))
    columns: dict[str, Any] = {}
    for method, entry in report.methods.items():
        life = entry.life_hot_spot
        columns[f"{method}.parameter"] = float(entry.at_hot_spot.value[0])
        columns[f"{method}.life"] = float(life.cycles) if life is not None else float("nan")
        columns[f"{method}.life_note"] = entry.life_message
        columns[f"{method}.x"] = float(entry.hot_spot[0])
        columns[f"{method}.depth"] = float(entry.hot_spot[1])
    return columns


__all__ = [
    "OutputFunction",
    "fatigue",
    "reference_errors",
    "resolve",
    "resolve_all",
    "surface_stress",
]
