"""Write a run's files so they cannot be lost or mixed: all or nothing, one run at a time.

``write_results`` writes every file into a temporary directory beside the target and swaps
it into place at the end, so an interruption, a full disk or a crash leaves either the old
output or the new one. A marker file identifies a fretbem output, which is replaced whole;
any other non-empty directory is refused unless ``overwrite=True``. A lock file beside the
target stops two runs writing the same directory. File names derived from step names are
sanitised (:func:`fretbem.verification.checks.safe_names`).
Writers are pluggable: ``register_writer``.

CSV cells whose text starts with ``= + - @`` (a formula to spreadsheet programs) are written
with a leading ``'`` (OWASP "CSV injection"); numbers are written as numbers.
"""

from __future__ import annotations

import csv
import importlib
import json
import os
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import attrs
import numpy as np

from fretbem.contact.law import STATE_NAMES
from fretbem.errors import InputError
from fretbem.output import figures as plot
from fretbem.output import fretting as fretting_
from fretbem.output import vtk as vtk_
from fretbem.output.labelled import write_netcdf_files
from fretbem.output.report import write_report
from fretbem.validators import flag
from fretbem.verification.checks import check_steps

from .staging import (  # noqa: F401 - re-exported: the output API of one release
    MARKER,
    SPACE_MARGIN,
    OutputError,
    OutputExistsError,
    OutputLockedError,
    check_free_space,
    csv_cell,
    output_lock,
    prepare_output,
    staged_directory,
)

#: units and sign conventions of every results.csv column (written to units.json and the docs)
CSV_COLUMNS = {
    "step": ("", "load step name (text; cells starting with = + - @ are prefixed with ')"),
    "x": ("mm", "pair position, x coordinate of the lower body's contact node"),
    "p": ("MPa", "contact pressure on the lower body, > 0 in compression"),
    "q": ("MPa", "shear traction of the upper body on the lower, along +x (the pair tangent)"),
    "un": ("mm", "relative normal displacement, upper minus lower, along the lower normal"),
    "ut": ("mm", "relative tangential displacement (accumulated slip), upper minus lower, +x"),
    "state": ("", "separated, stick or slip"),
}
#: units of the per-step summary.json keys (errors are fractions: 0.01 is 1 %)
SUMMARY_KEYS = {
    "P": ("N/mm", "normal load per unit thickness, > 0 presses the upper body down"),
    "Q": ("N/mm", "tangential load per unit thickness on the upper body, along +x"),
    "sigma_B": ("MPa", "bulk stress of the specimen along x, > 0 in tension (0 without one)"),
    "contact": ("mm", "[from, to]: x of the first and last pair in contact; null: none"),
    "stick_zones": ("mm", "every computed stick zone as [from, to] (first to last stick pair)"),
    "slip_zones": (
        "mm",
        "every computed slip zone as {from, to, sign}; sign '+' or '-' of its mean shear",
    ),
    "theory_stick_zone": (
        "mm",
        "[e - c, e + c]: the closed form's stick zone (offset e by the bulk stress, "
        "Nowell-Hills); null without a closed form",
    ),
    "hertz": (
        "N/mm, mm, MPa",
        "top level: P, the Hertz half-width a and peak pressure p0 of the closed form; null "
        "where none applies",
    ),
    "e_p_max": ("fraction of p0", "max |p - p_exact| / p0 (Hertz peak pressure); null: no theory"),
    "e_q_max": ("fraction of f p0", "max |q - q_exact| / (f p0); null without theory"),
    "e_p_l2": ("fraction of p0", "RMS over the zone of p - p_exact, / p0"),
    "e_q_l2": ("fraction of f p0", "RMS over the zone of q - q_exact, / (f p0)"),
    "est_p_max, est_p_l2": (
        "fraction of p0",
        "estimated discretisation error of the step's p (max, RMS) from two levels of the "
        "contact mesh; null: no estimate (accuracy.estimate_reason says why)",
    ),
    "est_q_max, est_q_l2": ("fraction of f p0", "the same for q, / (f p0)"),
    "delta": (
        "mm",
        "tangential displacement of the pad's loading block against the specimen's held end "
        "(the datum a 2D displacement needs), +x",
    ),
    "approach": ("mm", "normal approach of the pad's loading block against the same datum"),
    "M": (
        "N mm/mm",
        "moment the pad's loading block applies to the pad about the rig's pivot ([rig] "
        "pivot_height above the first-contact point; default the block's line), "
        "counterclockwise (x right, y up) > 0; null where the pad's model gives none",
    ),
    "theta": (
        "rad",
        "rotation of the actuator holding the pad's block, counterclockwise > 0: the block's "
        "own plus M / k_r ([rig] stiffness_rotation); 0 when the block does not rotate",
    ),
    "tilt": ("rad", "the pad block's own rotation about the pivot, counterclockwise > 0"),
    "control": (
        "",
        "per direction (normal, tangential): force or displacement; rotation: rotation "
        "(the actuator's imposed, 0 by default) or moment",
    ),
    "integral_p": ("N/mm", "integral of p over the contact face"),
    "integral_q": ("N/mm", "integral of q over the contact face"),
    "iterations": ("", "Newton iterations of the step"),
    "residuals": ("", "Newton residual norms"),
    "stick, slip, separated": ("", "pair counts"),
    "seconds": ("s", "wall time of the step"),
    "checks": ("", "per check: residual, limit, passed (see fretbem.verification.checks)"),
    "phases": (
        "s",
        "top level: wall time of each phase of the run (build, solve with every accuracy "
        "level, compare, fatigue, then each writer as 'write <name>', e.g. write stress; "
        "json and report write last and are not in it)",
    ),
    "accuracy": (
        "",
        "top level: mesh (fixed or adaptive), levels (pairs of every level solved, the last "
        "is the result), seconds (all levels), estimate_reason (null, or why no estimate)",
    ),
}


#: the module of a scene file's optional analyses ([stress], [fatigue], [wear]): their
#: requests, runs, writers and reports (:mod:`fretbem.output.analyses`)
ANALYSES = "fretbem.output.analyses"


def analyses():
    """:mod:`fretbem.output.analyses`, loaded on first use: only a run that has a
    ``[stress]``, ``[fatigue]`` or ``[wear]`` table loads the stress, fatigue and wear
    packages (~70 ms of start-up that a plain run, e.g. ``fretbem demo``, does not pay)."""
    return importlib.import_module(ANALYSES)


# -- writer registry ----------------------------------------------------------------------------
@attrs.frozen(eq=False)
class WriteContext:
    """What the writers of one run read: the result and what was computed beside it.

    Attributes
    ----------
    result : SimulationResult
    checks : list of dict, optional
        The result checks' records (summary.json).
    compare : tuple of SimulationResult
        Further results drawn in the figures.
    steps : sequence of str, optional
        The steps the figures draw.
    stress : StressRequest, optional
        A ``[stress]`` request, evaluated by the "stress" writer.
    fatigue : FatigueReport, optional
        A fatigue assessment, written by the "fatigue" writer.
    wear : WearReport, optional
        A wear history, written by the "wear" writer.
    writers : tuple of str
        The names of every writer of this run (a writer may add figures only when
        "figures" is among them).
    """

    result: object
    checks: Sequence[dict] | None = None
    compare: tuple = ()
    steps: Sequence[str] | None = None
    stress: object = None
    fatigue: object = None
    writers: tuple[str, ...] = ()
    wear: object = None
    cache: dict = attrs.field(factory=dict)  # what one writer computed for the others
    phases: dict = attrs.field(factory=dict)  # seconds per phase (summary.json "phases")
    progress: Callable | None = None  # progress(description, total) -> bar


@attrs.frozen
class Writer:
    """A named output: ``write(context, directory)`` (or ``write(result, directory)`` for a
    writer registered with ``context=False``), run into the run's staging directory.

    ``default`` writers run unless ``writers=`` names others; ``needs`` ("stress",
    "fatigue") makes a default writer run only when the run carries that result.
    """

    name: str
    write: Callable
    default: bool = True
    context: bool = True
    needs: str = ""

    def __call__(self, context: WriteContext, directory: Path):
        if self.context:
            return self.write(context, directory)
        return self.write(context.result, directory)


WRITERS: dict[str, Writer] = {}


def register_writer(
    name: str, write: Callable, *, default: bool = True, context: bool = False, needs: str = ""
) -> Writer:
    """Add a writer that ``write_results`` can run (``write(result, directory)`` unless
    ``context=True``, then ``write(WriteContext, directory)``)."""
    writer = Writer(name, write, default, context, needs)
    WRITERS[name] = writer
    return writer


def write_csv(result, path: Path) -> Path:
    """results.csv: one row per pair per step: step, x, p, q, un, ut, state (see CSV_COLUMNS)."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(CSV_COLUMNS))
        for s in result.steps:
            name = csv_cell(s.name)
            columns = np.column_stack(
                [s.x, s.pressure, s.shear, s.normal_displacement, s.tangential_displacement]
            ).tolist()
            states = np.asarray(s.states)
            writer.writerows(
                [name, *(repr(v) for v in row), STATE_NAMES[int(states[k])]]
                for k, row in enumerate(columns)
            )
    return path


def _json_default(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} to JSON")


def _finite(value):
    """Replace NaN and infinities (not JSON) with None, recursively."""
    if isinstance(value, float) and not np.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def write_json(
    result, path: Path, checks: Sequence[dict] | None = None, phases: dict | None = None
) -> Path:
    """summary.json: ``result.summary()`` with a ``units`` table, ``"errors_are"``, per
    step the residual, limit and outcome of every result check (``checks``), and the
    seconds of each phase of the run (``phases``)."""
    summary = dict(result.summary())
    if phases:
        summary["phases"] = {k: float(v) for k, v in phases.items()}
    if checks is not None:
        summary["steps"] = [
            {**step, "checks": {k: r.as_dict() for k, r in records.items()}}
            for step, records in zip(summary["steps"], checks, strict=True)
        ]
    fretting = fretting_.summary(result)
    if fretting is not None:
        summary["fretting"] = fretting
    summary["units"] = {k: v[0] for k, v in SUMMARY_KEYS.items()}
    if fretting is not None:
        summary["units"]["fretting"] = {k: v[0] for k, v in fretting_.CYCLE_KEYS.items()}
    summary["errors_are"] = "fractions (0.01 = 1 %)"
    text = json.dumps(_finite(summary), indent=2, default=_json_default, allow_nan=False)
    path.write_text(text + "\n")
    return path


def write_units(path: Path) -> Path:
    """units.json: unit and sign convention of every results.csv column and summary key."""
    table = {
        "system": "mm, N, MPa; forces per unit thickness (N/mm); plane strain unless the "
        "scene sets plane_stress",
        "results.csv": {k: {"unit": u, "meaning": m} for k, (u, m) in CSV_COLUMNS.items()},
        "summary.json": {k: {"unit": u, "meaning": m} for k, (u, m) in SUMMARY_KEYS.items()},
        "summary.json fretting": {
            k: {"unit": u, "meaning": m} for k, (u, m) in fretting_.CYCLE_KEYS.items()
        },
        "loops.csv": {
            k: {"unit": u, "meaning": m} for k, (u, m) in fretting_.LOOPS_COLUMNS.items()
        },
        "slip.csv": {k: {"unit": u, "meaning": m} for k, (u, m) in fretting_.SLIP_COLUMNS.items()},
    }
    path.write_text(json.dumps(table, indent=2) + "\n")
    return path


# -- the built-in writers -----------------------------------------------------------------------
def _write_csv(context: WriteContext, directory: Path) -> Path:
    return write_csv(context.result, directory / "results.csv")


def _write_json(context: WriteContext, directory: Path) -> Path:
    # the time of every phase so far, the other writers' included (json runs after them)
    return write_json(context.result, directory / "summary.json", context.checks, context.phases)


def _write_units(context: WriteContext, directory: Path) -> Path:
    return write_units(directory / "units.json")


def _write_figures(context: WriteContext, directory: Path):
    return plot.save_figures([context.result, *context.compare], directory, steps=context.steps)


def _write_vtk(context: WriteContext, directory: Path):
    return vtk_.save_vtk(context.result, directory)


def _write_stress(context: WriteContext, directory: Path):
    return analyses().write_stress_files(context, directory)


def _write_fretting(context: WriteContext, directory: Path):
    return fretting_.write_fretting(context.result, directory, figures="figures" in context.writers)


def _write_report(context: WriteContext, directory: Path):
    info = context.result.describe()
    steps = [s.name for s in context.result.steps]
    name = f"{info['basis']}, {info['pairs']} pairs, steps {steps[0]}..{steps[-1]}"
    return write_report(directory, name=name)


def _write_netcdf(context: WriteContext, directory: Path):
    stress = None if context.stress is None else analyses().evaluated_stress(context)
    return write_netcdf_files(context, directory, stress)


def _write_fatigue(context: WriteContext, directory: Path):
    return analyses().write_fatigue_files(context, directory)


def _write_wear(context: WriteContext, directory: Path):
    return analyses().write_wear_files(context, directory)


for _name, _function, _needs in (
    ("csv", _write_csv, ""),
    ("json", _write_json, ""),
    ("units", _write_units, ""),
    ("figures", _write_figures, ""),
    ("vtk", _write_vtk, ""),
    ("stress", _write_stress, "stress"),
    ("fatigue", _write_fatigue, "fatigue"),
    ("fretting", _write_fretting, ""),
    ("wear", _write_wear, "wear"),
):
    register_writer(_name, _function, context=True, needs=_needs)
register_writer("netcdf", _write_netcdf, default=False, context=True)
#: report.html reads the other writers' files: it runs last whenever it is chosen
register_writer("report", _write_report, default=False, context=True)


def chosen_writers(
    names: Sequence[str] | None, context: WriteContext, *, figures=None, vtk=None
) -> list[Writer]:
    """The writers to run: ``names`` (each must be registered), else every default writer
    whose ``needs`` the run carries; the flags ``figures``/``vtk`` = False drop those two."""
    if names is None:
        chosen = [w for w in WRITERS.values() if w.default and (
            not w.needs or getattr(context, w.needs) is not None)]  # fmt: skip
    else:
        unknown = [n for n in names if n not in WRITERS]
        if unknown:
            raise InputError(
                f"no output writer {unknown[0]!r}; the registered writers are {sorted(WRITERS)}"
            )
        chosen = [WRITERS[n] for n in dict.fromkeys(names)]
    dropped = {n for n, flag in (("figures", figures), ("vtk", vtk)) if flag is False}
    # summary.json carries every other writer's time; the report reads every other file
    chosen.sort(key=lambda w: {"json": 1, "report": 2}.get(w.name, 0))
    return [w for w in chosen if w.name not in dropped]


# -- the directory ------------------------------------------------------------------------------
def write_results(
    result,
    directory: str | os.PathLike,
    *,
    writers: Sequence[str] | None = None,
    overwrite: bool = False,
    compare: Sequence = (),
    steps: Sequence[str] | None = None,
    stress=None,
    fatigue=None,
    wear=None,
    check: bool = True,
    figures: bool | None = None,
    vtk: bool | None = None,
    extra: Sequence[Callable] = (),
    phases: dict | None = None,
    progress: Callable | None = None,
) -> Path:
    """Write a run into ``directory`` through its writers: the one output mechanism.

    ``writers`` names the registered writers to run (``WRITERS``: csv, json, units, figures,
    vtk, stress, fatigue, wear, and any registered by a plugin); by default every default
    writer whose input the run carries (``stress``: a StressRequest, ``fatigue``: a FatigueReport,
    ``wear``: a :class:`~fretbem.wear.assess.WearReport`).
    ``compare`` are further results drawn in the figures; ``steps`` chooses the steps drawn.
    All files go to a temporary directory beside ``directory`` first; it replaces the target
    whole at the end (old output or new, never a mix). Returns the directory.

    Every result check (:func:`fretbem.verification.checks.check_steps`) runs first and its
    residuals go to summary.json; a failed check raises its ResultCheckError and writes
    nothing (``check=False`` skips them, for inspecting a failed run). Raises OutputError
    (one-line message) when the directory cannot be used or written. ``figures=False`` and
    ``vtk=False`` drop those writers, and ``extra`` callables ``write(directory)`` run last
    (both kept for one release: name the writers instead). ``phases`` (seconds by phase name)
    go to summary.json's ``phases`` with each writer's time ("write <name>");
    ``progress(description, total)`` makes the bars of long writers (the stresses).
    """
    check, figures, vtk = (
        flag("check", check),
        flag("figures", figures, none=True),
        flag("vtk", vtk, none=True),
    )
    if isinstance(writers, str):
        raise InputError(
            f"writers must be a list of writer names, got the string {writers!r}; give "
            f"[{writers!r}]"
        )
    target = prepare_output(directory, overwrite=overwrite)
    records = check_steps(result) if check else None  # a failed check writes nothing
    context = WriteContext(result, records, tuple(compare), steps, stress, fatigue, wear=wear)
    chosen = chosen_writers(writers, context, figures=figures, vtk=vtk)
    context = attrs.evolve(
        context, writers=tuple(w.name for w in chosen), phases=dict(phases or {}),
        progress=progress,
    )  # fmt: skip
    bar = progress("writing", len(chosen)) if progress is not None else None
    with staged_directory(target, overwrite=overwrite) as staging:
        for writer in chosen:
            tic = time.perf_counter()
            writer(context, staging)
            context.phases[f"write {writer.name}"] = time.perf_counter() - tic
            if bar is not None:
                bar.update(1)
        if bar is not None:
            bar.close()
        for write in extra:
            write(staging)
    return target
