"""The [wear] scene table: parsed, validated by name, documented; run from a scene file."""

import csv
import json
from pathlib import Path

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

import numpy as np
import pytest

import fretbem
import fretbem.pipeline
import fretbem.scenes.builder
import fretbem.wear.run
from fretbem.app import cli
from fretbem.scenes.file import scene_from_data
from fretbem.wear.law import ArchardWear, EnergyWear, WearInputError
from fretbem.wear.request import wear_markdown_table, wear_request_from_dict

ROOT = Path(__file__).resolve().parents[3]

HALF_PLANE_SCENE = """
[pad]
radius = 70.0
model = "half-plane"
[specimen]
shape = "flat"
model = "half-plane"
[material]
E = 73400.0
nu = 0.33
[contact]
friction = 0.3
pairs = 21
[load]
steps = ["A", "B", "C", "D", "E"]
P = 100.0
Q = [0.0, 18.0, 0.0, -18.0, 0.0]
increments = 3
"""


def test_a_full_table_is_parsed():
    request = wear_request_from_dict(
        {"law": {"pad": "archard", "specimen": "energy"}, "pad": 1e-8, "specimen": 2e-4,
         "cycles": 5000, "cycle": ["B", "C"], "increments": 4, "max_change": 2e-4,
         "safety": 0.4, "max_jump": 100, "output": [100], "assess": [2000]}
    )  # fmt: skip
    assert request.laws == {"upper": ArchardWear(1e-8), "lower": EnergyWear(2e-4)}
    assert request.cycles == 5000 and request.cycle == ("B", "C") and request.increments == 4
    assert request.control.max_change == 2e-4 and request.control.max_jump == 100
    assert request.outputs == (0, 100, 5000) and request.assess == (0, 2000, 5000)


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"pad": 1e-4, "specimen": 1e-4}, r"\[wear\] cycles is missing"),
        ({"cycles": 10, "specimen": 1e-4}, r"\[wear\] pad is missing"),
        ({"cycles": 10, "pad": -1.0, "specimen": 1e-4}, r"\[wear\] pad: .*>= 0"),
        ({"cycles": 10, "pad": "a", "specimen": 1e-4}, r"\[wear\] pad must be a number"),
        ({"cycles": 0, "pad": 1e-4, "specimen": 1e-4}, r"\[wear\] cycles must be >= 1"),
        ({"cycles": 1.5, "pad": 1e-4, "specimen": 1e-4}, r"cycles must be a whole number"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "output": [11]}, r"output asks for N = 11"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "safety": 3.0}, r"lets the jump diverge"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "scheme": "rk4"}, r"scheme must be one of"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "relative_change": 0}, r"relative_change"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "speed": 3}, r"unknown key\(s\) \['speed'\]"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "law": "glue"}, r"glue"),
        ({"cycles": 10, "pad": 0, "specimen": 0, "law": {"pad": "energy"}}, r"name the pad"),
    ],
)
def test_bad_tables_are_refused_by_name(table, message):
    with pytest.raises(fretbem.errors.InputError, match=message):
        wear_request_from_dict(table)


def test_the_docs_table_is_the_key_table():
    assert wear_markdown_table() in (ROOT / "docs" / "scene-format.md").read_text()


def test_a_cycle_naming_an_unknown_step_is_refused():
    data = tomllib.loads(HALF_PLANE_SCENE)
    data["wear"] = {"cycles": 10, "pad": 0.0, "specimen": 1e-4, "cycle": ["B", "Z"]}
    with pytest.raises(WearInputError, match="cycle names step 'Z'"):
        fretbem.run_scene(scene_from_data(data))


def test_adaptive_mesh_is_refused():
    data = tomllib.loads(HALF_PLANE_SCENE)
    data["contact"]["mesh"] = "adaptive"
    del data["contact"]["pairs"]
    data["wear"] = {"cycles": 10, "pad": 0.0, "specimen": 1e-4}
    with pytest.raises(fretbem.errors.InputError, match=r"\[wear\] needs a fixed contact mesh"):
        fretbem.run_scene(scene_from_data(data))


def _rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_scene_file_runs_and_writes_every_wear_file(tmp_path, basis):
    text = HALF_PLANE_SCENE + (
        '\n[wear]\nlaw = "energy"\npad = 1e-4\nspecimen = 2e-4\ncycles = 3000\n'
        "output = [500]\nassess = [0, 3000]\n"
        '[stress]\nbody = "lower"\nsteps = ["B"]\n[[stress.line]]\nx = -0.3\ndepth = 0.5\nn = 5\n'
    )
    text = text.replace("pairs = 21", f'pairs = 21\nbasis = "{basis}"')
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    quick = ["--no-figures", "--no-vtk"] if basis == "lagrange2" else []  # nurbs draws them
    code = cli.main(["run", str(tmp_path / "scene.toml"), "--out", str(out), *quick])
    assert code == 0
    rows = _rows(out / "wear_summary.csv")
    assert [int(r["N"]) for r in rows] == [0, 500, 3000]
    final = rows[-1]
    assert float(final["volume_specimen"]) == pytest.approx(
        2e-4 / 1000 * float(final["energy"]), rel=1e-12
    )
    assert float(final["volume_pad"]) == pytest.approx(0.5 * float(final["volume_specimen"]))
    wear = _rows(out / "wear.csv")
    assert len(wear) == 3 * 4 * 21  # N x cycle steps x pairs
    for name in ("wear.csv", "wear_summary.csv", "wear_jumps.csv"):  # plain numbers only
        cells = [cell for row in _rows(out / name) for cell in row.values()]
        assert not [cell for cell in cells if "(" in cell], name  # e.g. 'np.float64(0.1)'
    jumps = _rows(out / "wear_jumps.csv")
    assert sum(int(j["delta_N"]) for j in jumps) == 3000
    summary = json.loads((out / "wear.json").read_text())
    assert summary["settings"]["laws"]["specimen"] == {"law": "EnergyWear", "alpha": 2e-4}
    assert summary["units"]["wear.csv"]["p"]["unit"] == "MPa"
    drawn = ("wear_profiles.png", "wear_pressure.png", "wear_evolution.png", "wear.pvd")
    for name in drawn:
        assert (out / name).exists() == (not quick)
    assert (out / "vtk" / "wear_N3000_specimen.vtp").exists() == (not quick)
    for n in (0, 3000):
        assert (out / f"wear_N{n}" / "stress_line_0.csv").exists()
    before = np.loadtxt(out / "wear_N0" / "stress_line_0.csv", delimiter=",", skiprows=1,
                        usecols=range(2, 6), max_rows=5)  # fmt: skip
    after = np.loadtxt(out / "wear_N3000" / "stress_line_0.csv", delimiter=",", skiprows=1,
                       usecols=range(2, 6), max_rows=5)  # fmt: skip
    assert not np.allclose(before, after)  # the worn contact stresses the specimen otherwise


def test_the_example_parses():
    data = tomllib.loads((ROOT / "examples" / "fretting_wear_rig.toml").read_text())
    request = wear_request_from_dict(scene_from_data(data).extras["wear"])
    assert request.laws["lower"] == EnergyWear(1.8e-4)


def test_a_waveform_history_wears_one_load_cycle_at_a_time():
    """[load.cycle]: the wear cycle is the first load cycle's steps (c1.*), not the whole
    waveform; the result matches the same drive written as named steps (within 0.5 %)."""
    data = tomllib.loads(HALF_PLANE_SCENE.replace("pairs = 21", "pairs = 31\nzone = 2.5"))
    data["load"] = {"P": 100.0, "cycle": {"delta": 0.02, "cycles": 3, "increments": 12,
                                          "shape": "triangle"}}  # fmt: skip
    data["wear"] = {"pad": 1e-4, "specimen": 3e-4, "cycles": 5000, "scheme": "implicit",
                    "relative_change": 0.1}  # fmt: skip
    scene = scene_from_data(data)
    simulation, _ = fretbem.scenes.builder.build(scene)
    wear = fretbem.pipeline.wear_request(scene.extras).simulation(simulation)
    assert [s.name for s in wear.preload_steps] == ["press"]
    assert len(wear.cycle_steps) == 12 and wear.cycle_steps[0].name.startswith("c1.")
    result = fretbem.wear.run.run_wear(wear)
    assert result.final.profile.max_depth("lower") == pytest.approx(2.9313e-3, rel=0.005)
