"""Output directories that cannot be lost or mixed: staging, the swap into place, the lock.

Every file of a run goes into a temporary directory beside the target, swapped into place
at the end, so an interruption, a full disk or a crash leaves either the old output or the
new one. A marker file identifies a fretbem output, which is replaced whole; any other
non-empty directory is refused unless ``overwrite=True``. A lock file beside the target
stops two runs writing the same directory.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import glob
import json
import os
import shutil
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

from fretbem.errors import OutputError
from fretbem.validators import flag

__all__ = [
    "MARKER",
    "SPACE_MARGIN",
    "OutputError",
    "OutputExistsError",
    "OutputLockedError",
    "add_output_file",
    "check_free_space",
    "output_lock",
    "prepare_output",
    "staged_directory",
]

MARKER = ".fretbem-output"
#: free bytes required beyond the estimated size of the files (filesystem metadata, margins)
SPACE_MARGIN = 16 * 2**20


class OutputExistsError(OutputError):
    """The target is a non-empty directory that is not a previous fretbem output."""


class OutputLockedError(OutputError):
    """Another run is writing the same output directory."""


def _protected(path: Path) -> bool:
    """Directories never replaced: the root, home, the working directory and its parents."""
    cwd = Path.cwd().resolve()
    return path == Path(path.anchor) or path == Path.home().resolve() or path in (cwd, *cwd.parents)


def _written_files(directory: Path) -> list[str]:
    """Every file below ``directory`` (relative, sorted), the marker excepted."""
    return sorted(
        p.relative_to(directory).as_posix()
        for p in directory.rglob("*")
        if p.is_file() and p.name != MARKER
    )


def _not_replaceable(target: Path) -> str:
    """Why the non-empty ``target`` is not a fretbem output that may be replaced whole ("" if
    it is): the marker must name this directory and list every file in it, so a copied
    marker or a file a user added is never deleted without --overwrite."""
    marker = target / MARKER
    if not marker.is_file():
        return "is not empty and is not a previous fretbem output"
    try:
        record = json.loads(marker.read_text())
    except (OSError, ValueError):
        return f"has an unreadable {MARKER} file"
    if not isinstance(record, dict) or "files" not in record or "directory" not in record:
        return "was written by an older fretbem (its marker lists no files)"
    if record["directory"] != str(target):
        return (
            f"holds a fretbem marker written for {record['directory']} (copied or moved), so its "
            "files cannot be told from yours"
        )
    extra = sorted(set(_written_files(target)) - set(record["files"]))
    if extra:
        shown = ", ".join(extra[:3]) + (f" and {len(extra) - 3} more" if len(extra) > 3 else "")
        return f"holds files fretbem did not write ({shown}); move them out first"
    return ""


def prepare_output(directory: str | os.PathLike, *, overwrite: bool = False) -> Path:
    """Check, before any computation, that ``directory`` may be (re)written; returns its path.

    Refuses (OutputExistsError / OutputError) a file, a non-empty directory without the
    fretbem marker (unless ``overwrite``), a protected directory, and an unwritable parent.
    """
    overwrite = flag("overwrite", overwrite)  # ("no" would be true, and overwrite)
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
    if target.is_dir() and any(target.iterdir()) and not overwrite:
        why = _not_replaceable(target)
        if why:
            raise OutputExistsError(
                f"output directory {target} {why}; choose another --out, or pass --overwrite to "
                "replace it whole"
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
        _remove_previous(staging, target)  # staging now holds the old output
        return
    old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-", dir=target.parent))
    os.rename(target, old / "previous")  # the old output stays whole until the new one is in
    os.rename(staging, target)
    _remove_previous(old, target)


def _remove_previous(previous: Path, target: Path) -> None:
    """Delete the swapped-out old output; the new one is in place whatever happens here."""
    try:
        shutil.rmtree(previous)
    except OSError as err:
        raise OutputError(
            f"the new output is in {target}, but the previous one could not be removed from "
            f"{previous} ({err.strerror or err}); delete it by hand"
        ) from None


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
        name = glob.escape(target.name)  # 'r*' or 'results[1]' must not match other runs
        for stale in (*target.parent.glob(f".{name}.tmp-*"),
                      *target.parent.glob(f".{name}.old-*")):  # fmt: skip
            shutil.rmtree(stale, ignore_errors=True)  # left by a killed run; we hold the lock
        staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent))
        try:
            os.chmod(staging, 0o777 & ~_umask())  # mkdtemp makes it private (0700)
            yield staging
            record = {
                "fretbem_output": 2,
                "written": time.strftime("%Y-%m-%dT%H:%M:%S"),
                "directory": str(target),
                "files": _written_files(staging),
            }
            (staging / MARKER).write_text(json.dumps(record, indent=1))
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


def csv_cell(value) -> str | float:
    """A CSV cell that spreadsheets read as text, never as a formula (OWASP CSV injection)."""
    if isinstance(value, str) and value[:1] in ("=", "+", "-", "@", "\t", "\r"):
        return "'" + value
    return value


def add_output_file(directory: str | os.PathLike, name: str, text: str) -> Path:
    """Add the file ``name`` to a finished fretbem output (e.g. a report made afterwards):
    written whole (a temporary file renamed into place) under the output's lock, and listed
    in its marker so the folder stays replaceable by the next run."""
    target = Path(os.fspath(directory)).expanduser().resolve()
    if not target.is_dir():
        raise OutputError(f"{target} is not a directory; give the --out folder of a fretbem run")
    why = _not_replaceable(target) if any(target.iterdir()) else "is empty"
    if why:
        raise OutputError(f"{target} {why}; give the --out folder of a fretbem run")
    with output_lock(target):
        path = target / name
        handle, temporary = tempfile.mkstemp(prefix=f".{name}.", dir=target)
        try:
            with os.fdopen(handle, "w", encoding="utf-8") as stream:
                stream.write(text)
            os.chmod(temporary, 0o666 & ~_umask())
            os.replace(temporary, path)
        except OSError as err:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(temporary)
            raise OutputError(f"could not write {path}: {err.strerror or err}") from None
        marker = target / MARKER
        record = json.loads(marker.read_text())
        record["files"] = sorted(set(record["files"]) | {name})
        marker.write_text(json.dumps(record, indent=1))
    return path
