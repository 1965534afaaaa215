"""A scene file's optional analyses, ``[stress]``, ``[fatigue]`` and ``[wear]``: their tables
read and checked, carried out, written and reported.

The run pipeline, the writers and the command line reach this module through
:func:`fretbem.output.write.analyses`, for a run that has one of the tables: a run without
them (``fretbem demo``, most scenes) does not load the stress, fatigue and wear packages,
~70 ms of every start-up.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from fretbem.fatigue import fatigue_request_from_dict, run_fatigue
from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.fatigue.output import format_report, write_fatigue
from fretbem.stress.limits import check_points, request_points
from fretbem.stress.request import stress_request_from_dict
from fretbem.stress.run import evaluate_stress_request, write_stress_result
from fretbem.wear.assess import assess, format_wear
from fretbem.wear.request import wear_request_from_dict
from fretbem.wear.run import run_wear

from .wear import write_wear

__all__ = [
    "check_requests",
    "evaluated_stress",
    "fatigue_of",
    "format_report",
    "format_wear",
    "requests",
    "wear_of",
    "wear_request",
    "write_fatigue_files",
    "write_stress_files",
    "write_wear_files",
]


def requests(extras: Mapping) -> tuple:
    """The ``[stress]`` and ``[fatigue]`` requests of ``extras`` (None for an absent table)."""
    stress = stress_request_from_dict(extras["stress"]) if "stress" in extras else None
    fatigue = fatigue_request_from_dict(extras["fatigue"]) if "fatigue" in extras else None
    return stress, fatigue


def wear_request(extras: Mapping):
    """The ``[wear]`` request of ``extras``."""
    return wear_request_from_dict(extras["wear"])


def check_requests(simulation, stress, fatigue) -> None:
    """Refuse stress and fatigue requests too large for the machine, with the estimate."""
    pair = simulation.pair
    dofs = max(int(getattr(b, "dofs", 0) or 0) for b in (pair.upper, pair.lower))
    points = request_points(stress)
    grid = getattr(stress, "grid", None)
    where = (
        f"[stress.grid] nx x ny = {grid.nx} x {grid.ny}"
        if grid is not None and 2 * grid.nx * grid.ny > points
        else "[stress] (points, lines and grid)"
    )
    check_points(points, dofs, where)
    if fatigue is not None:
        nx, nd = fatigue.map_points
        check_points(nx * nd, dofs, "[fatigue] map_points")


def fatigue_of(result, request, progress=None):
    """The fatigue assessment of ``request`` on the solved ``result``."""
    return run_fatigue(SimulationStressHistory(result), request, progress=progress)


def wear_of(wear, request, fatigue_request, progress=None):
    """The wear history of the wear simulation ``wear`` and its assessments at the
    request's ``assess`` N (fatigue there when ``fatigue_request`` is given)."""
    result = run_wear(wear, progress=progress)
    return result, assess(result, request.assess, fatigue_request)


def evaluated_stress(context):
    """The run's StressResult, evaluated once per write (writers share it)."""
    if context.stress is None:
        return None
    if "stress" not in context.cache:
        context.cache["stress"] = evaluate_stress_request(
            context.result, context.stress, progress=context.progress
        )
    return context.cache["stress"]


def write_stress_files(context, directory: Path):
    """The "stress" writer: the ``[stress]`` request evaluated and written."""
    return write_stress_result(context.result, context.stress, evaluated_stress(context), directory)


def write_fatigue_files(context, directory: Path):
    """The "fatigue" writer: the fatigue report's files (figures with the "figures" writer)."""
    return write_fatigue(directory, context.fatigue, figures="figures" in context.writers)


def write_wear_files(context, directory: Path):
    """The "wear" writer: the wear history's files, figures and VTK with those writers."""
    chosen = context.writers
    return write_wear(
        directory, context.wear, stress=context.stress, figures="figures" in chosen,
        vtk="vtk" in chosen,
    )  # fmt: skip
