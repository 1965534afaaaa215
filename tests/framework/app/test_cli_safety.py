"""The fretbem command refuses bad options before computing and ends every failure in one line."""

from __future__ import annotations

import errno
import re
import subprocess
import sys
from pathlib import Path

import pytest

from fretbem.app import cli, commands
from fretbem.bem import resources
from fretbem.output import write as output

EXAMPLE = Path(__file__).parents[3] / "examples" / "cattaneo_mindlin.toml"
FAST = ["--no-figures", "--no-vtk"]


def scene(tmp_path: Path, **lines: str) -> str:
    """The example scene file with whole lines replaced (key = new value), 21 pairs."""
    text = EXAMPLE.read_text()
    for key, value in {"pairs": "21", **lines}.items():
        text, count = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
        assert count == 1, f"example scene has no line '{key} = ...'"
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return str(path)


@pytest.fixture
def no_run(patch_run):
    """Fail the test if a simulation is started (the option must be refused before)."""

    def forbidden(*args, **kwargs):
        raise AssertionError("the run started before the bad option was refused")

    patch_run(forbidden)


def one_line_error(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    errors = [line for line in err if "error" in line or "failed" in line]
    assert len(errors) == 1, err
    assert "Traceback" not in "\n".join(err)
    return errors[0]


def test_no_arguments_prints_help(capsys):
    assert cli.main([]) == 0
    assert "usage: fretbem" in capsys.readouterr().out


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["--version"])
    assert info.value.code == 0
    assert re.match(r"fretbem \d+\.\d+", capsys.readouterr().out)


@pytest.mark.parametrize("pairs", ["0", "-3", "abc", "2.5"])
def test_bad_pair_counts_are_usage_errors(pairs, capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["demo", "--pairs", pairs, *FAST])
    assert info.value.code == 2
    assert "--pairs" in capsys.readouterr().err


def test_unknown_compare_family_is_refused_before_the_run(no_run, tmp_path, capsys):
    """Reproducer: --compare hermite failed only after the main run, losing it."""
    assert cli.main(["demo", "--compare", "hermite", "--out", str(tmp_path / "o")]) == 2
    line = one_line_error(capsys)
    assert "hermite" in line and "nurbs" in line
    assert not (tmp_path / "o").exists()


def test_unknown_figure_step_is_refused_before_the_run(no_run, tmp_path, capsys):
    assert cli.main(["demo", "--steps", "B", "Z", "--out", str(tmp_path / "o")]) == 2
    assert "['Z']" in one_line_error(capsys)


def test_foreign_out_directory_is_refused_before_the_run(no_run, tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("mine")
    assert cli.main(["demo", "--out", str(tmp_path), *FAST]) == 2
    assert "--overwrite" in one_line_error(capsys)
    assert [p.name for p in tmp_path.iterdir()] == ["notes.txt"]


def test_huge_pair_count_is_refused_quickly_with_the_estimate(
    no_run, tmp_path, monkeypatch, capsys
):
    """Reproducer: --pairs 20001 spent minutes in a dense knot insertion, then ran out of
    memory. Now the bodies are built by sparse refinement and the run is refused."""
    monkeypatch.setattr(resources, "available_memory", lambda: 16.0 * 2**30)
    assert cli.main(["demo", "--pairs", "20001", "--out", str(tmp_path / "o"), *FAST]) == 2
    line = one_line_error(capsys)
    # estimated from the scene's keys before any body is built (80316 once built)
    assert re.search(r"about 80\d\d\d boundary DOFs", line) and "available memory: 16 GB" in line
    assert "[contact] pairs" in line
    assert not (tmp_path / "o").exists()


def test_duplicate_step_names_are_refused(no_run, tmp_path, capsys):
    path = scene(tmp_path, steps='["A", "B", "B", "D", "E"]')
    assert cli.main(["run", path, "--out", str(tmp_path / "o"), *FAST]) == 2
    assert "unique" in one_line_error(capsys)


def test_too_small_zone_exits_non_zero_naming_zone(tmp_path, capsys):
    """Reproducer: zone = 0.5 ran, exit 0, with 1820 MPa at the zone edge."""
    path = scene(tmp_path, zone="0.5")
    assert cli.main(["run", path, "--out", str(tmp_path / "o"), *FAST]) == 1
    assert "`zone`" in one_line_error(capsys)
    assert not (tmp_path / "o").exists()


def test_near_gross_sliding_exits_non_zero(tmp_path, capsys):
    """Reproducer: Q = 0.9999 f P gave a 1e9 mm block displacement and exit 0."""
    path = scene(tmp_path, Q="[0.0, 29.997]", steps='["A", "B"]')
    assert cli.main(["run", path, "--out", str(tmp_path / "o"), *FAST]) == 1
    line = one_line_error(capsys)
    assert "stick-zone width" in line and "pair spacing" in line
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "lines", [{"E": "1e16"}, {"P": "1e-8", "Q": "[0.0, 1.8e-9, 0.0, -1.8e-9, 0.0]"}]
)
def test_extreme_materials_balance_or_refuse(tmp_path, capsys, lines):
    """Reproducer: E = 1e16 or P = 1e-8 gave unbalanced tractions silently: now either the
    equilibrium check passes or the run exits 1 with the equilibrium error."""
    code = cli.main(["run", scene(tmp_path, **lines), "--out", str(tmp_path / "o"), *FAST])
    if code == 1:
        assert "equilibrium" in one_line_error(capsys)
    else:
        assert code == 0


def test_os_and_memory_errors_end_in_one_line(patch_run, tmp_path, monkeypatch, capsys):
    """A full disk while writing and a MemoryError while solving: one line each, exit 2."""

    def full(result, path):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(output, "write_csv", full)
    assert cli.main(["demo", "--pairs", "21", "--out", str(tmp_path / "o"), *FAST]) == 2
    assert "No space left on device" in one_line_error(capsys)
    assert not (tmp_path / "o").exists()

    def oom(*args, **kwargs):
        raise MemoryError

    patch_run(oom)
    assert cli.main(["demo", "--pairs", "21", "--out", str(tmp_path / "o"), *FAST]) == 2
    assert "out of memory" in one_line_error(capsys)


def test_interrupt_is_exit_130_without_traceback(patch_run, tmp_path, monkeypatch, capsys):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    patch_run(interrupted)
    assert cli.main(["demo", "--out", str(tmp_path / "o"), *FAST]) == 130
    assert "interrupted" in capsys.readouterr().err


def test_console_script_bad_scene_has_no_traceback(tmp_path):
    """One subprocess: an unreadable scene file ends in one line on stderr, exit 2."""
    bad = tmp_path / "bad.toml"
    bad.write_text("[scene\npairs = ")
    done = subprocess.run(
        [sys.executable, "-m", "fretbem.app.cli", "run", str(bad), "--out", str(tmp_path / "o")],
        capture_output=True, text=True, check=False, timeout=120,
    )  # fmt: skip
    assert done.returncode == 2
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1


def test_long_run_prints_a_progress_line_with_the_estimate(tmp_path, monkeypatch, capsys):
    """A run estimated above two seconds says so on stderr before it starts."""
    monkeypatch.setattr(resources, "SECONDS_PER_DOF2", 1e-4)
    assert cli.main(["demo", "--pairs", "21", "--out", str(tmp_path / "o"), *FAST]) == 0
    err = capsys.readouterr().err
    assert "fretbem: running, estimated" in err and "boundary DOFs" in err


def test_step_progress_lines_are_rate_limited(capsys):
    """The per-step progress printer writes at most once per interval, and the last step."""
    progress = commands.StepProgress(1000, interval=3600.0)
    for k in range(1, 1001):
        progress(k, 1000, type("Step", (), {"name": f"S{k}"})())
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("fretbem: step 1000/1000 (S1000) done")


def test_progress_hook_is_passed_only_to_a_run_that_takes_it():
    """run(simulation, progress=...) once the simulation offers the hook; never otherwise."""
    long = type("Estimate", (), {"seconds": 10.0})()
    simulation = type("Simulation", (), {"steps": (1, 2)})()

    def with_hook(simulation, *, progress=None): ...

    def without(simulation): ...

    option = commands._progress_option(with_hook, simulation, long)
    assert isinstance(option["progress"], commands.StepProgress)
    assert commands._progress_option(without, simulation, long) == {}


def test_out_containing_the_scene_is_refused_even_with_overwrite(no_run, tmp_path, capsys):
    """--overwrite on the scene's own folder would delete the scene: refused."""
    path = scene(tmp_path)
    assert cli.main(["run", path, "--out", str(tmp_path), "--overwrite", *FAST]) == 2
    assert "contains the scene file" in one_line_error(capsys)
    assert Path(path).is_file()


def test_sigterm_cleans_up_like_ctrl_c(patch_run, tmp_path, monkeypatch, capsys):
    """kill (SIGTERM) during a run: exit 130, no output, no temporary directory."""
    import os
    import signal

    def killed(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)

    patch_run(killed)
    before = signal.getsignal(signal.SIGTERM)
    assert cli.main(["demo", "--pairs", "21", "--out", str(tmp_path / "o"), *FAST]) == 130
    assert signal.getsignal(signal.SIGTERM) is before
    assert list(tmp_path.iterdir()) == []
