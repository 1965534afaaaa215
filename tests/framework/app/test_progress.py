"""Progress bars (terminal only, never with --quiet, after 2 s) and the time of each phase
in summary.json."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest

from fretbem.app import cli, progress
from fretbem.app.progress import Bars, NullBar

ROOT = Path(__file__).resolve().parents[3]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


class _Recorder:
    """A bars factory that records every bar: description, total, updates, closed."""

    def __init__(self):
        self.bars = []

    def __call__(self, description, total=None):
        record = {"description": description, "total": total, "done": 0, "closed": False}
        self.bars.append(record)

        class Bar:
            def update(self, n=1):
                record["done"] += n

            def close(self):
                record["closed"] = True

        return Bar()


def test_bars_only_on_a_terminal_and_never_quiet(monkeypatch):
    assert isinstance(Bars(stream=io.StringIO())("x", 3), NullBar)
    assert isinstance(Bars(stream=_Terminal(), quiet=True)("x", 3), NullBar)
    monkeypatch.setattr(progress, "DELAY", 0.0)
    stream = _Terminal()
    hook = Bars(stream=stream).steps(4)
    for k in range(1, 5):
        hook(k, 4, None)
    assert "fretbem: load steps" in stream.getvalue() and "/4 [" in stream.getvalue()


def test_long_phases_report_their_progress(tmp_path):
    from fretbem.fatigue import CattaneoMindlinCycle, fatigue_request_from_dict, run_fatigue
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import load_scene
    from fretbem.stress import evaluate_stress_request, stress_request_from_dict

    bars = _Recorder()
    cycle = CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5,
                                 sigma_bulk_max=80.0, nu=0.342)  # fmt: skip
    request = fatigue_request_from_dict(
        {"material": "Ti-6Al-4V", "map_points": [7, 3], "methods": ["swt", "findley"],
         "constants": {"findley_k": 0.3}}
    )  # fmt: skip
    run_fatigue(cycle, request, progress=bars)
    run = run_scene(load_scene(ROOT / "examples" / "cattaneo_mindlin.toml", pairs=21))
    stress = stress_request_from_dict(
        {"steps": ["B"], "points": [[0.0, -0.1]],
         "line": [{"x": "trailing-edge", "depth": 0.2, "n": 3}] * 2}
    )  # fmt: skip
    evaluate_stress_request(run.result, stress, progress=bars)
    run.write(tmp_path / "out", writers=["csv", "json"], progress=bars)
    assert [(b["description"], b["total"], b["done"], b["closed"]) for b in bars.bars] == [
        ("fatigue", 3, 3, True), ("stresses", 3, 3, True), ("writing", 2, 2, True),
    ]  # fmt: skip


def test_adaptive_levels_report_their_progress():
    from fretbem.accuracy.modes import Accuracy, solve
    from fretbem.scenes.builder import build
    from fretbem.scenes.file import load_scene

    simulation, _ = build(load_scene(ROOT / "examples" / "cattaneo_mindlin.toml", pairs=21))
    bars = _Recorder()
    result = solve(simulation, Accuracy(mesh="adaptive", tolerance=0.5, budget=31), bars=bars)
    (bar,) = bars.bars
    assert bar["description"] == "adaptive levels" and bar["closed"]
    # the uniform level, then one unit per aligned level (each may re-solve to settle)
    assert 2 <= bar["done"] <= bar["total"] and bar["done"] <= len(result.accuracy.levels)


def test_summary_holds_the_time_of_every_phase(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["demo", "--pairs", "21", "--no-vtk", "--compare", "lagrange2", "--out",
                     str(out)]) == 0  # fmt: skip
    printed = capsys.readouterr()
    phases = json.loads((out / "summary.json").read_text())["phases"]
    assert list(phases)[:3] == ["build", "solve", "compare"]
    for name in ("write csv", "write units", "write figures", "write vtk"):
        assert (name in phases) is (name != "write vtk"), name
    assert all(v >= 0 for v in phases.values())
    assert "time by phase: build" in printed.out
    units = json.loads((out / "units.json").read_text())["summary.json"]
    assert units["phases"]["unit"] == "s"
    # --quiet: the tables print, no status line or bar on stderr
    assert cli.main(["demo", "--pairs", "21", "--no-vtk", "--no-figures", "--quiet", "--out",
                     str(tmp_path / "quiet")]) == 0  # fmt: skip
    printed = capsys.readouterr()
    assert printed.err == "" and "e_q max%" in printed.out


@pytest.mark.parametrize("flag", [[], ["--quiet"]])
def test_sweep_takes_quiet(flag):
    args = cli.parser().parse_args(["sweep", "x.toml", *flag])
    assert args.quiet is bool(flag)


def test_wear_cycles_advance_one_bar():
    from fretbem.pipeline import _cycle_bar

    bars = _Recorder()
    hook = _cycle_bar(bars, 100_000)
    for n in (1, 10, 5_000, 100_000):
        hook(n, 100_000)
    assert bars.bars == [
        {"description": "wear cycles", "total": 100_000, "done": 100_000, "closed": True}
    ]
    assert _cycle_bar(None, 10) is None
