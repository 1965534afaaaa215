"""Output that cannot be lost or mixed: fretbem.output.write.write_results and its guards."""

from __future__ import annotations

import csv
import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import attrs
import pytest

from fretbem.output import staging
from fretbem.output import write as output
from fretbem.output.write import (
    MARKER,
    OutputError,
    OutputExistsError,
    OutputLockedError,
    output_lock,
    prepare_output,
    write_results,
)
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import run
from fretbem.verification.checks import ContactZoneError

HOSTILE = ["A", "../../x", "/abs/path", "=1+2", "B/1", "z" * 300, "-cmd", "@SUM(A1)"]


@pytest.fixture(scope="module")
def result():
    """The reference cycle with 21 nurbs pairs."""
    return run(cattaneo_mindlin(CattaneoMindlinScene(pairs=21)))


def _files(directory: Path) -> set[str]:
    return {p.relative_to(directory).as_posix() for p in directory.rglob("*") if p.is_file()}


def _renamed(result, names):
    steps = tuple(attrs.evolve(s, name=n) for s, n in zip(result.steps, names, strict=False))
    return attrs.evolve(result, steps=steps)


def test_fresh_output_has_marker_units_and_checks(result, tmp_path):
    """A new directory gets the marker, units.json, and per-step check residuals."""
    out = write_results(result, tmp_path / "out", figures=False)
    assert (out / MARKER).is_file()
    units = json.loads((out / "units.json").read_text())
    assert set(units["results.csv"]) == {"step", "x", "p", "q", "un", "ut", "state"}
    assert units["results.csv"]["p"]["unit"] == "MPa"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["errors_are"].startswith("fractions")
    for step in summary["steps"]:
        assert set(step["checks"]) == {"equilibrium", "zone_edge", "tangential_hold"}
        assert all(c["passed"] for c in step["checks"].values())
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temp or lock left


def test_foreign_non_empty_directory_is_refused_unless_overwrite(result, tmp_path):
    """Reproducer: --out pointing at a user's folder silently mixed files into it."""
    mine = tmp_path / "thesis"
    mine.mkdir()
    (mine / "chapter1.tex").write_text("precious")
    with pytest.raises(OutputExistsError, match="--overwrite"):
        write_results(result, mine, figures=False, vtk=False)
    assert _files(mine) == {"chapter1.tex"}
    write_results(result, mine, figures=False, vtk=False, overwrite=True)
    assert "chapter1.tex" not in _files(mine) and (mine / MARKER).is_file()


def test_previous_output_is_replaced_whole(result, tmp_path):
    """Reproducer: stale VTK files of an older run stayed beside the new ones."""
    out = write_results(result, tmp_path / "out", figures=False)
    assert "vtk/B_upper.vtp" in _files(out)
    write_results(result, out, figures=False, vtk=False)
    assert not any(name.startswith("vtk/") for name in _files(out))
    assert {"results.csv", "summary.json"} <= _files(out)


@pytest.mark.parametrize("where", ["notes.txt", "vtk/my_view.pvsm"])
def test_a_file_the_user_added_is_never_deleted_silently(result, tmp_path, where):
    """Reproducer: files a user put inside a previous output were deleted on the next run."""
    out = write_results(result, tmp_path / "out", figures=False)
    (out / where).write_text("mine")
    with pytest.raises(OutputExistsError, match=r"holds files fretbem did not write \(" + where):
        write_results(result, out, figures=False)
    assert (out / where).read_text() == "mine"
    write_results(result, out, figures=False, overwrite=True)  # said explicitly: replaced
    assert not (out / where).exists()


def test_a_copied_marker_does_not_make_a_folder_replaceable(result, tmp_path):
    """Reproducer: copying the marker file into any folder made fretbem replace it."""
    out = write_results(result, tmp_path / "out", figures=False, vtk=False)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "thesis.tex").write_text("precious")
    (mine / ".fretbem-output").write_bytes((out / ".fretbem-output").read_bytes())
    with pytest.raises(OutputExistsError, match="marker written for"):
        write_results(result, mine, figures=False, vtk=False)
    assert (mine / "thesis.tex").read_text() == "precious"


@pytest.mark.parametrize(
    "failure", [KeyboardInterrupt(), OSError(errno.ENOSPC, "No space left on device")]
)
def test_interruption_or_full_disk_leaves_the_old_output(result, tmp_path, failure):
    """Ctrl-C or a full disk in the middle of writing: the old output, whole; no temp dir."""
    out = write_results(result, tmp_path / "out", figures=False, vtk=False)
    before = {name: (out / name).read_bytes() for name in _files(out)}

    def broken(result, directory):
        (directory / "partial.bin").write_bytes(b"x")
        raise failure

    output.register_writer("broken", broken, default=False)
    try:
        with pytest.raises((KeyboardInterrupt, OutputError)) as info:
            write_results(result, out, figures=False, vtk=False, writers=["broken"])
    finally:
        del output.WRITERS["broken"]
    if isinstance(failure, OSError):
        assert "No space left on device" in str(info.value)
        assert "\n" not in str(info.value)
    assert {name: (out / name).read_bytes() for name in _files(out)} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_failed_check_writes_nothing(tmp_path):
    """A result that fails a check is refused before any file is written."""
    bad = run(cattaneo_mindlin(CattaneoMindlinScene(pairs=21, zone=0.5)), check=False)
    with pytest.raises(ContactZoneError):
        write_results(bad, tmp_path / "out", figures=False, vtk=False)
    assert list(tmp_path.iterdir()) == []


def test_second_writer_on_the_same_directory_refuses(result, tmp_path):
    """Two runs on one --out cannot interleave: the lock holder's pid is named."""
    target = prepare_output(tmp_path / "out")
    with output_lock(target):
        with pytest.raises(OutputLockedError, match=f"process {os.getpid()}"):
            write_results(result, target, figures=False, vtk=False)
    write_results(result, target, figures=False, vtk=False)  # released


def test_stale_lock_of_a_dead_process_is_taken_over(result, tmp_path):
    """A lock left by a killed run does not block the next one."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()  # fmt: skip
    (tmp_path / "out.fretbem-lock").write_text(dead + "\n")
    write_results(result, tmp_path / "out", figures=False, vtk=False)
    assert not (tmp_path / "out.fretbem-lock").exists()


def test_hostile_step_names_stay_inside_and_are_not_formulas(result, tmp_path):
    """Reproducers: steps named ../../x, /abs/path, B/1, 300 chars; CSV formula cells."""
    hostile = _renamed(result, HOSTILE[: len(result.steps)])
    out = write_results(hostile, tmp_path / "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    vtk = sorted(p.name for p in (out / "vtk").iterdir())
    assert len(vtk) == 4 * len(result.steps)
    assert {"x_upper.vtp", "abs_path_lower.vtp", "1_2_upper.vtp", "B_1_lower.vtp"} <= set(vtk)
    with open(out / "results.csv", newline="") as handle:
        cells = {row[0] for row in list(csv.reader(handle))[1:]}
    assert cells == {"A", "../../x", "/abs/path", "'=1+2", "B/1"}
    assert json.loads((out / "summary.json").read_text())["steps"][3]["step"] == "=1+2"


@pytest.mark.parametrize("value", ["=cmd|' /C calc'!A0", "+1", "-2+3", "@SUM(1)", "\tx", "ok"])
def test_csv_cells_are_never_formulas(value):
    """OWASP CSV injection: text starting with = + - @ tab CR gets a leading quote."""
    cell = output.csv_cell(value)
    assert cell == value if value == "ok" else cell == "'" + value


def test_output_paths_that_cannot_work_are_refused_before_computing(tmp_path):
    """A file, the working directory, an unwritable parent: refused by prepare_output."""
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="is a file"):
        prepare_output(tmp_path / "file")
    with pytest.raises(OutputError, match="cannot write beside"):
        prepare_output(tmp_path / "file" / "out")
    with pytest.raises(OutputError, match="refusing to replace"):
        prepare_output(".", overwrite=True)
    with pytest.raises(OutputError, match="not a valid path"):
        prepare_output("a\0b")


def test_short_disk_space_is_refused_before_the_vtk_writer(result, tmp_path, monkeypatch):
    """Reproducer: the VTK writer segfaulted on a full disk; now the space is checked first
    and the files are written by Python (errors are OSError, never a crash)."""
    usage = staging.shutil.disk_usage(tmp_path)
    monkeypatch.setattr(
        staging.shutil, "disk_usage", lambda path: usage._replace(free=output.SPACE_MARGIN)
    )
    with pytest.raises(OutputError, match="not enough disk space for the VTK files"):
        write_results(result, tmp_path / "out", figures=False)
    assert list(tmp_path.iterdir()) == []


def test_long_history_figures_are_capped_and_summarised(result, tmp_path):
    """Reproducer: one panel per step made unreadable, huge figures for long histories.
    100 steps: 6 panels (first and last included), capped sizes, a history summary."""
    import matplotlib.image as mpimg

    from fretbem.output import figures as plot

    steps = tuple(attrs.evolve(s, name=f"S{k}") for k, s in enumerate(result.steps * 20))
    long = attrs.evolve(result, steps=steps)
    chosen = plot.default_steps([s.name for s in steps])
    assert len(chosen) == plot.MAX_PANELS and chosen[0] == "S0" and chosen[-1] == "S99"
    paths = plot.save_figures(long, tmp_path)
    assert {p.name for p in paths} == {
        "tractions.png", "displacements.png", "states.png", "history.png"
    }  # fmt: skip
    for path in paths:
        height, width = mpimg.imread(path).shape[:2]
        assert width <= 1800 and height <= 1000, (path.name, width, height)
    with pytest.raises(plot.FigureStepsError, match="at most 6"):
        plot.save_figures(long, tmp_path, steps=[f"S{k}" for k in range(7)])
    with pytest.raises(plot.FigureStepsError, match="not in the results"):
        plot.save_figures(long, tmp_path, steps=["nope"])


def test_docs_list_every_column_with_its_unit():
    """docs/how-to/output-files.rst has a row for every results.csv column and summary key."""
    page = (Path(__file__).parents[3] / "docs" / "how-to" / "output-files.rst").read_text()
    rows = {line.split()[0] for line in page.splitlines() if line.startswith("   ") and
            line.strip() and not line.strip().startswith("=")}  # fmt: skip
    assert set(output.CSV_COLUMNS) <= rows
    for key, (unit, _) in output.SUMMARY_KEYS.items():
        assert key.split(",")[0] in page and (not unit or unit in page)


def test_replacement_without_atomic_exchange_is_whole(result, tmp_path, monkeypatch):
    """Where renameat2 is missing the old output is renamed aside, then the new one in."""
    monkeypatch.setattr(staging, "_exchange", lambda a, b: False)
    out = write_results(result, tmp_path / "out", figures=False)
    write_results(result, out, figures=False, vtk=False)
    assert not any(name.startswith("vtk/") for name in _files(out))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_staging_left_by_a_killed_run_is_removed(result, tmp_path):
    """SIGKILL leaves .out.tmp-*; the next run (holding the lock) removes it."""
    (tmp_path / ".out.tmp-killed").mkdir()
    (tmp_path / ".out.tmp-killed" / "results.csv").write_text("partial")
    write_results(result, tmp_path / "out", figures=False, vtk=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


@pytest.mark.parametrize(("name", "other"), [("results[1]", "results1"), ("r*", "rx"),
                                             ("a?c", "abc")])  # fmt: skip
def test_glob_characters_in_out_leave_other_runs_staging_alone(result, tmp_path, name, other):
    """Reproducer: --out 'results[1]' or 'r*' deleted another run's staging directory in the
    same folder (the stale-staging cleanup globbed the name unescaped)."""
    theirs = tmp_path / f".{other}.tmp-abc123"
    theirs.mkdir()
    (theirs / "results.csv").write_text("another run's file")
    write_results(result, tmp_path / name, figures=False, vtk=False)
    assert (theirs / "results.csv").read_text() == "another run's file"
    assert (tmp_path / name / "results.csv").exists()


def test_a_failed_removal_of_the_old_output_says_the_new_one_is_in(result, tmp_path, monkeypatch):
    """Reproducer: when removing the swapped-out old output failed, the message said the old
    output 'was left as it was' although the new one had replaced it."""
    out = write_results(result, tmp_path / "out", figures=False, vtk=False)

    def refuse(path, ignore_errors=False, **kwargs):
        if not ignore_errors:
            raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(staging.shutil, "rmtree", refuse)
    with pytest.raises(OutputError, match=r"the new output is in .*delete it by hand") as info:
        write_results(result, out, figures=False, vtk=False)
    assert "left as it was" not in str(info.value)
    assert (out / "results.csv").exists()
