"""Write a run's files so they cannot be lost or mixed: all or nothing, one run at a time.

``write_results`` writes every file into a temporary directory beside the target and swaps
it into place at the end, so an interruption, a full disk or a crash leaves either the old
output or the new one. A marker file identifies a fretbem output, which is replaced whole;
any other non-empty directory is refused unless ``overwrite=True``. A lock file beside the
target stops two runs writing the same directory. File names derived from step names are
sanitised (:func:`fretbem.checks.safe_names`). Writers are pluggable: ``register_writer``.

CSV cells whose text starts with ``= + - @`` (a formula to spreadsheet programs) are written
with a leading ``'`` (OWASP "CSV injection"); numbers are written as numbers.
"""

from __future__ import annotations

import contextlib
import csv
import ctypes
import ctypes.util
import json
import os
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import attrs
import numpy as np

MARKER = ".fretbem-output"
#: free bytes required beyond the estimated size of the files (filesystem metadata, margins)
SPACE_MARGIN = 16 * 2**20
STATE_NAMES = ("separated", "stick", "slip")

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
    "integral_p": ("N/mm", "integral of p over the contact face"),
    "integral_q": ("N/mm", "integral of q over the contact face"),
    "iterations": ("", "Newton iterations of the step"),
    "residuals": ("", "Newton residual norms"),
    "stick, slip, separated": ("", "pair counts"),
    "seconds": ("s", "wall time of the step"),
    "checks": ("", "per check: residual, limit, passed (see fretbem.checks)"),
    "accuracy": (
        "",
        "top level: mesh (fixed or adaptive), levels (pairs of every level solved, the last "
        "is the result), seconds (all levels), estimate_reason (null, or why no estimate)",
    ),
}


class OutputError(RuntimeError):
    """The output directory cannot be used or written; nothing at the target was changed."""


class OutputExistsError(OutputError):
    """The target is a non-empty directory that is not a previous fretbem output."""


class OutputLockedError(OutputError):
    """Another run is writing the same output directory."""


# -- writer registry ----------------------------------------------------------------------------
@attrs.frozen
class Writer:
    """A named writer: ``write(result, directory, **options) -> list[Path]``."""

    name: str
    write: Callable
    default: bool = True


WRITERS: dict[str, Writer] = {}


def register_writer(name: str, write: Callable, *, default: bool = True) -> Writer:
    """Add a writer (e.g. stresses, fatigue) that ``write_results`` runs into the temp dir."""
    writer = Writer(name, write, default)
    WRITERS[name] = writer
    return writer


# -- the CSV and JSON files ---------------------------------------------------------------------
def csv_cell(value) -> str | float:
    """A CSV cell that spreadsheets read as text, never as a formula (OWASP CSV injection)."""
    if isinstance(value, str) and value[:1] in ("=", "+", "-", "@", "\t", "\r"):
        return "'" + value
    return value


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


def write_json(result, path: Path, checks: Sequence[dict] | None = None) -> Path:
    """summary.json: ``result.summary()`` with a ``units`` table, ``"errors_are"`` and, per
    step, the residual, limit and outcome of every result check (``checks``)."""
    summary = dict(result.summary())
    if checks is not None:
        summary["steps"] = [
            {**step, "checks": {k: r.as_dict() for k, r in records.items()}}
            for step, records in zip(summary["steps"], checks, strict=True)
        ]
    summary["units"] = {k: v[0] for k, v in SUMMARY_KEYS.items()}
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
    }
    path.write_text(json.dumps(table, indent=2) + "\n")
    return path


# -- the directory ------------------------------------------------------------------------------
def _protected(path: Path) -> bool:
    """Directories never replaced: the root, home, the working directory and its parents."""
    cwd = Path.cwd().resolve()
    return path == Path(path.anchor) or path == Path.home().resolve() or path in (cwd, *cwd.parents)


def prepare_output(directory: str | os.PathLike, *, overwrite: bool = False) -> Path:
    """Check, before any computation, that ``directory`` may be (re)written; returns its path.

    Refuses (OutputExistsError / OutputError) a file, a non-empty directory without the
    fretbem marker (unless ``overwrite``), a protected directory, and an unwritable parent.
    """
    raw = os.fspath(directory)
    if not raw or "\0" in raw:
        raise OutputError(f"output directory {raw!r} is not a valid path")
    target = Path(raw).expanduser().resolve()
    if target.exists() and not target.is_dir():
        raise OutputError(f"output path {target} is a file, not a directory; choose another --out")
    if _protected(target):
        raise OutputError(
            f"refusing to replace {target} (the root, home or working directory, or one of its "
            "parents); choose a new directory for --out"
        )
    if target.is_dir() and not (target / MARKER).is_file() and any(target.iterdir()):
        if not overwrite:
            raise OutputExistsError(
                f"output directory {target} is not empty and is not a previous fretbem output; "
                "choose another --out, empty it, or pass --overwrite to replace it whole"
            )
    parent = target.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=parent):
            pass
    except OSError as err:
        raise OutputError(f"cannot write beside {target}: {err.strerror or err}") from None
    return target


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@contextlib.contextmanager
def output_lock(target: Path) -> Iterator[Path]:
    """Hold ``<target>.fretbem-lock`` beside the target; a second run refuses while it exists.

    A lock left by a process that no longer runs (killed) is taken over.
    """
    lock = target.with_name(target.name + ".fretbem-lock")
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            try:
                pid = int(lock.read_text().split()[0])
            except (OSError, ValueError, IndexError):
                pid = -1
            if pid > 0 and _pid_alive(pid):
                raise OutputLockedError(
                    f"another fretbem run (process {pid}) is writing {target}; wait for it or "
                    f"choose another --out (remove {lock} if that process is not fretbem)"
                ) from None
            with contextlib.suppress(FileNotFoundError):
                lock.unlink()  # stale: its process is gone
            continue
        with os.fdopen(fd, "w") as handle:
            handle.write(f"{os.getpid()}\n")
        break
    else:  # pragma: no cover - lost a race twice
        raise OutputLockedError(f"could not lock {target}; another run is starting on it")
    try:
        yield lock
    finally:
        with contextlib.suppress(FileNotFoundError):
            lock.unlink()


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Atomically swap two paths (Linux renameat2 RENAME_EXCHANGE); False if unsupported."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p]
    renameat2.argtypes += [ctypes.c_uint]
    done = renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    return done == 0


def _move_into_place(staging: Path, target: Path) -> None:
    """Replace ``target`` by ``staging``: an atomic exchange where possible, else two renames."""
    if not target.exists():
        os.rename(staging, target)
        return
    if _exchange(staging, target):
        shutil.rmtree(staging)  # now holds the old output
        return
    old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-", dir=target.parent))
    os.rename(target, old / "previous")  # the old output stays whole until the new one is in
    os.rename(staging, target)
    shutil.rmtree(old)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def check_free_space(directory: Path, needed: float, what: str) -> None:
    """Raise OutputError before writing ``needed`` bytes where fewer are free."""
    free = shutil.disk_usage(directory).free
    if free < needed + SPACE_MARGIN:
        raise OutputError(
            f"not enough disk space for the {what}: about {needed / 2**20:.1f} MB needed, "
            f"{free / 2**20:.1f} MB free in {directory}; free some space or choose another --out"
        )


@contextlib.contextmanager
def staged_directory(directory: str | os.PathLike, *, overwrite: bool = False) -> Iterator[Path]:
    """Yield an empty temporary directory beside ``directory`` that replaces it whole on exit.

    The target is checked (:func:`prepare_output`) and locked (:func:`output_lock`); the
    staging directory gets the fretbem marker. On any exception the staging directory is
    removed and the target left as it was; an OSError becomes a one-line OutputError.
    Any writer of a run's files (results, studies, stresses) can write through it.
    """
    target = prepare_output(directory, overwrite=overwrite)
    with output_lock(target):
        for stale in (*target.parent.glob(f".{target.name}.tmp-*"),
                      *target.parent.glob(f".{target.name}.old-*")):  # fmt: skip
            shutil.rmtree(stale, ignore_errors=True)  # left by a killed run; we hold the lock
        staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent))
        try:
            os.chmod(staging, 0o777 & ~_umask())  # mkdtemp makes it private (0700)
            (staging / MARKER).write_text(
                json.dumps({"fretbem_output": 1, "written": time.strftime("%Y-%m-%dT%H:%M:%S")})
            )
            yield staging
            _move_into_place(staging, target)
        except OSError as err:
            shutil.rmtree(staging, ignore_errors=True)
            where = f" ({err.filename})" if err.filename else ""
            raise OutputError(
                f"could not write the output: {err.strerror or err}{where}; {target} was left "
                "as it was"
            ) from None
        except BaseException:
            shutil.rmtree(staging, ignore_errors=True)
            raise


def write_results(
    result,
    directory: str | os.PathLike,
    *,
    figures: bool = True,
    vtk: bool = True,
    overwrite: bool = False,
    compare: Sequence = (),
    steps: Sequence[str] | None = None,
    writers: Sequence[str] | None = None,
    check: bool = True,
    extra: Sequence[Callable] = (),
) -> Path:
    """Write results.csv, summary.json, units.json, figures and VTK files into ``directory``.

    All files go to a temporary directory beside ``directory`` first; it replaces the target
    whole at the end (old output or new, never a mix). ``compare`` are further results drawn
    in the figures; ``steps`` chooses the steps drawn; ``writers`` names registered writers
    to run (default: those registered with ``default=True``); ``extra`` are further
    callables ``write(directory)`` of this run (stresses, fatigue). Returns the directory.
    Every result check (:func:`fretbem.checks.check_steps`) runs first and its residuals go
    to summary.json; a failed check raises its ResultCheckError and writes nothing
    (``check=False`` skips them, for inspecting a failed run). Raises OutputError (one-line
    message) when the directory cannot be used or written.
    """
    from .checks import check_steps

    target = prepare_output(directory, overwrite=overwrite)
    records = check_steps(result) if check else None  # a failed check writes nothing
    chosen = [w for w in WRITERS.values() if w.default] if writers is None else []
    for name in writers or ():
        if name not in WRITERS:
            raise OutputError(f"no output writer {name!r}; registered: {sorted(WRITERS)}")
        chosen.append(WRITERS[name])
    with staged_directory(target, overwrite=overwrite) as staging:
        write_csv(result, staging / "results.csv")
        write_json(result, staging / "summary.json", records)
        write_units(staging / "units.json")
        if figures:
            from . import plot

            plot.save_figures([result, *compare], staging, steps=steps)
        if vtk:
            from . import vtk_

            vtk_.save_vtk(result, staging)
        for writer in chosen:
            writer.write(result, staging)
        for write in extra:
            write(staging)
    return target
