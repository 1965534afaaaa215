"""The fretbem command: bases, run and demo, as a user calls them."""

import csv
import json
import subprocess
import sys

import pytest

from fretbem.app import cli


def test_bases_lists_both_families(capsys):
    """`fretbem bases` lists nurbs and lagrange2 with a one-line description each."""
    assert cli.main(["bases"]) == 0
    lines = capsys.readouterr().out.splitlines()
    names = [line.split()[0] for line in lines]
    assert {"nurbs", "lagrange2"} <= set(names)
    assert all(len(line.split(maxsplit=1)) == 2 for line in lines)


def test_run_scene_file(tmp_path, capsys):
    """`fretbem run` prints the per-step table and writes results.csv and summary.json."""
    code = cli.main(
        [
            "run",
            "examples/cattaneo_mindlin.toml",
            "--pairs",
            "31",
            "--out",
            str(tmp_path),
            "--no-figures",
            "--no-vtk",
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "e_q max%     est" in out and "assembly" in out
    assert "fixed mesh, levels 16, 31 pairs" in out  # the companion level gives the estimate
    rows = list(csv.reader(open(tmp_path / "results.csv")))
    assert rows[0] == ["step", "x", "p", "q", "un", "ut", "state"]
    assert len(rows) == 1 + 5 * 31
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert [s["step"] for s in summary["steps"]] == list("ABCDE")
    assert summary["steps"][2]["e_q_max"] < 0.1
    assert summary["accuracy"]["levels"] == [16, 31]
    assert 0 < summary["steps"][2]["est_q_max"] < 1


def test_unknown_basis_is_a_clear_error(capsys):
    """An uninstalled family exits 2 and names the installed ones."""
    assert cli.main(["demo", "--basis", "hermite", "--no-figures", "--no-vtk"]) == 2
    err = capsys.readouterr().err
    assert "hermite" in err and "nurbs" in err and "lagrange2" in err


def test_console_script_runs_demo(tmp_path):
    """The installed console script runs the reference demo end to end."""
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "fretbem.app.cli",
            "demo",
            "--out",
            str(tmp_path),
            "--no-figures",
            "--no-vtk",
        ],
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "nurbs (degree 2), 61 node pairs" in done.stdout
    assert (tmp_path / "results.csv").exists()


ENDING = """
import atexit, sys
from fretbem.app.cli import main
atexit.register(lambda: print("exit handler ran", flush=True))
sys.argv = ["fretbem", "demo", "--basis", sys.argv[1], "--no-figures", "--no-vtk", "--quiet",
            "--pairs", "31", "--no-estimate", "--out", sys.argv[2]]
print("last line", main())
"""


@pytest.mark.parametrize(("basis", "code"), [("nurbs", 0), ("hermite", 2)])
def test_console_demo_ends_with_its_code_output_and_exit_handlers(tmp_path, basis, code):
    """The console script's demo ends its process in main() (no interpreter teardown), with
    the command's exit code, everything printed flushed and the exit handlers run."""
    done = subprocess.run(
        [sys.executable, "-c", ENDING, basis, str(tmp_path / "out")],
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )
    assert done.returncode == code, done.stderr
    assert "last line" not in done.stdout  # main() did not return
    assert done.stdout.rstrip().endswith("exit handler ran")
    if code == 0:
        assert "31 node pairs" in done.stdout
        assert (tmp_path / "out" / "results.csv").exists()
    else:
        assert "hermite" in done.stderr


@pytest.mark.parametrize("pairs", ["60"])
def test_impossible_pair_count(pairs, capsys):
    """lagrange2 cannot place an even number of nodes: the error says which counts work."""
    assert cli.main(["demo", "--basis", "lagrange2", "--pairs", pairs, "--no-figures"]) == 2
    assert "choose pairs = 2 k + 1" in capsys.readouterr().err


def test_a_reader_that_stops_reading_ends_the_command_quietly():
    """`fretbem plugins | head -1`: a closed pipe ends the command with the shell's SIGPIPE
    code (141) and nothing on stderr, not "error: Broken pipe" and exit 2. The reader here
    closes before the command writes (its imports take longer), so the write always fails."""
    process = subprocess.Popen(
        [sys.executable, "-m", "fretbem.app.cli", "plugins"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    process.stdout.close()
    err = process.stderr.read()
    assert process.wait(timeout=120) == cli.SIGPIPE_EXIT, err
    assert err == ""
