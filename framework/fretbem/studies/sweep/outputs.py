"""Extra per-case output columns: functions named ``"module:function"`` in a sweep.

An output function takes the case's ``SimulationResult`` and its scene dict and returns a
mapping of column name to number or string; the sweep calls it on the worker after each
solved case (so it must be importable there) and an exception in it makes that case an
error row. This is the seam for stress and fatigue columns.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from importlib.metadata import entry_points
from typing import Any

import numpy as np

from fretbem.fatigue.critical_plane import DEFAULT_METHODS
from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.fatigue.request import fatigue_request_from_dict
from fretbem.fatigue.run import run_fatigue
from fretbem.stress.evaluate import StressEvaluator

from .spec import SweepSpecError

OutputFunction = Callable[[Any, Mapping], Mapping[str, Any]]


#: entry-point group where a plugin registers further sweep outputs (name = "module:function")
ENTRY_POINTS = "fretbem.sweep_outputs"


def registered() -> dict[str, str]:
    """Every sweep output: short name -> ``"module:function"`` (built-ins and plugins)."""
    names = {name: f"{__name__}:{name}" for name in BUILT_IN}
    for entry in entry_points(group=ENTRY_POINTS):
        names.setdefault(entry.name, entry.value)
    return names


def resolve(name: str) -> OutputFunction:
    """The registered output ``name`` (short name or its ``"module:function"``).

    Only registered outputs are accepted: a sweep file cannot import and call an arbitrary
    installed function (``"os:getcwd"``). A plugin registers an output in the
    ``fretbem.sweep_outputs`` entry-point group.
    """
    names = registered()
    target = names.get(name) if isinstance(name, str) else None
    if target is None and isinstance(name, str) and name in names.values():
        target = name
    if target is None:
        raise SweepSpecError(
            f"[sweep] outputs: {name!r} is not a registered sweep output; registered: "
            f"{sorted(names)} (a plugin adds one in the {ENTRY_POINTS!r} entry-point group)"
        )
    module_name, _, attribute = target.partition(":")
    try:
        function = getattr(importlib.import_module(module_name), attribute)
    except (ImportError, AttributeError) as err:
        raise SweepSpecError(f"[sweep] outputs: cannot load {name!r} ({target}): {err}") from None
    if not callable(function):
        raise SweepSpecError(f"[sweep] outputs: {name!r} ({target}) is not a function")
    return function


def resolve_all(names: Sequence[str]) -> tuple[OutputFunction, ...]:
    """Every named output function, in order."""
    if isinstance(names, str):
        names = [names]
    return tuple(resolve(n) for n in names)


def declared_columns(names: Sequence[str], steps: Sequence[str], tables: Mapping) -> set | None:
    """The columns the outputs will add (for checking [[maps]] before solving); None when an
    output does not declare its columns (a plugin's without a ``columns`` attribute)."""
    columns: set[str] = set()
    for name in [names] if isinstance(names, str) else names:
        declare = getattr(resolve(name), "columns", None)
        if declare is None:
            return None
        columns |= set(declare(steps, tables))
    return columns


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


def _reference_columns(steps, tables) -> list[str]:
    return [f"{k}.{s}" for s in steps for k in ("e_p_max", "e_q_max")]


reference_errors.columns = _reference_columns  # type: ignore[attr-defined]


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


surface_stress.columns = lambda steps, tables: [  # type: ignore[attr-defined]
    "sxx_max",
    *(f"sxx_max.{s}" for s in steps),
]


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


def _fatigue_columns(steps, tables) -> list[str]:
    table = tables.get("fatigue") if isinstance(tables, Mapping) else None
    methods = DEFAULT_METHODS
    if isinstance(table, Mapping) and isinstance(table.get("methods"), (list, str)):
        methods = [table["methods"]] if isinstance(table["methods"], str) else table["methods"]
    keys = ("parameter", "life", "life_note", "x", "depth")
    return [f"{m}.{k}" for m in methods for k in keys]


fatigue.columns = _fatigue_columns  # type: ignore[attr-defined]

#: the built-in outputs, by short name
BUILT_IN = ("surface_stress", "fatigue", "reference_errors")


__all__ = [
    "BUILT_IN",
    "ENTRY_POINTS",
    "OutputFunction",
    "declared_columns",
    "fatigue",
    "reference_errors",
    "registered",
    "resolve",
    "resolve_all",
    "surface_stress",
]
