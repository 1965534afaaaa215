"""The public run pipeline: run_scene from Python equals fretbem run from the command line."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import fretbem
from fretbem.app import cli
from fretbem.errors import InputError
from fretbem.output.write import WRITERS, write_results
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import cattaneo_mindlin

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def _summary(out: Path) -> dict:
    data = json.loads((out / "summary.json").read_text())
    for step in data["steps"]:  # wall times differ between two runs
        step.pop("seconds")
    data.pop("accuracy", None)
    data.pop("timings", None)
    data["phases"] = sorted(data.get("phases", {}))  # the same phases, not the same times
    return data


def test_run_scene_equals_the_command_line(tmp_path):
    scene_file = EXAMPLES / "fretting_rig.toml"
    assert cli.main(["run", str(scene_file), "--out", str(tmp_path / "cli"), "--no-figures",
                     "--no-vtk", "--pairs", "31"]) == 0  # fmt: skip
    done = fretbem.run_scene(load_scene(scene_file), pairs=31)
    assert done.fatigue is not None and done.stress is not None
    out = done.write(tmp_path / "py", figures=False, vtk=False)
    cli_rows = (tmp_path / "cli" / "results.csv").read_text()
    assert (out / "results.csv").read_text() == cli_rows
    assert _summary(out) == _summary(tmp_path / "cli")
    assert json.loads((out / "fatigue.json").read_text()) == json.loads(
        (tmp_path / "cli" / "fatigue.json").read_text()
    )


def test_writers_choose_the_files(tmp_path):
    done = fretbem.run_scene(load_scene(EXAMPLES / "cattaneo_mindlin.toml"), pairs=21)
    out = done.write(tmp_path / "o", writers=["csv"])
    assert sorted(p.name for p in out.iterdir()) == [".fretbem-output", "results.csv"]
    with pytest.raises(InputError, match=r"no output writer 'cvs'; the registered writers are"):
        write_results(done.result, tmp_path / "p", writers=["cvs"])
    assert not (tmp_path / "p").exists()
    assert {"csv", "json", "units", "figures", "vtk", "stress", "fatigue"} <= set(WRITERS)
    rows = np.genfromtxt(out / "results.csv", delimiter=",", names=True, dtype=None,
                         encoding="utf-8")  # fmt: skip
    assert np.allclose(rows["p"][rows["step"] == "B"], done.result["B"].pressure)


def test_result_arrays_cannot_be_edited_in_place():
    """A result reports what was computed: editing it in place (which once wrote a doubled
    pressure beside a summary whose check had passed) raises instead."""
    result = fretbem.run(cattaneo_mindlin(pairs=21))
    step = result.steps[1]
    for name in ("x", "pressure", "shear", "normal_displacement", "tangential_displacement",
                 "states", "unknowns"):  # fmt: skip
        with pytest.raises(ValueError, match="read-only"):
            getattr(step, name)[:] *= 2
