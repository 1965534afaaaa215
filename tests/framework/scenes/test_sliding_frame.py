"""[contact] frame: the pair frame of finite sliding along an arc, from the scene file and
from Python (identical numbers), and every value without a meaning refused with the key."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.app.cli import main
from fretbem.pipeline import run_scene
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.spec import SceneFileError
from fretbem.sliding import run_sliding
from fretbem.testing.scenes import scene_data_with
from fretbem.wear.jump import JumpControl
from fretbem.wear.law import EnergyWear, WearInputError
from fretbem.wear.run import WearSimulation, run_wear

ROOT = Path(__file__).resolve().parents[3]
ARC = tomllib.loads((ROOT / "examples" / "gross_sliding_arc.toml").read_text())
FLAT = tomllib.loads((ROOT / "examples" / "gross_sliding.toml").read_text())
WEAR = tomllib.loads((ROOT / "examples" / "fretting_wear_sliding_arc.toml").read_text())
#: the small run of the tests: 21 pairs, 2 mm along the arc and back in 6 increments each
SMALL = {"contact__pairs": 21, "load__increments": [1, 6, 6]}


@pytest.mark.parametrize(
    ("base", "changes", "match"),
    [
        (ARC, {"contact__frame": "global"}, r"\[contact\] frame must be 'local' .* or 'shared' "
                                            r".*got 'global'"),
        (ARC, {"contact__frame": 1}, r"\[contact\] frame must be a string, got 1"),
        (ARC, {"contact__frame": "shared", "contact__sliding": False},
         r"\[contact\] frame = 'shared' .*sliding is off.*set \[contact\] sliding = true or "
         r"remove frame"),
        (FLAT, {"contact__frame": "local"}, r"\[contact\] frame = 'local' has no meaning on a "
                                            r"'flat' specimen.*remove frame"),
        (ARC, {"pad__frame": "shared"}, r"unknown key \['frame'\] in \[pad\]"),
        (ARC, {"specimen__frame": "shared"}, r"unknown key \['frame'\] in \[specimen\]"),
    ],
)  # fmt: skip
def test_bad_frames_are_refused_when_read(base, changes, match):
    """A frame is the pair's, not a face's: no [pad] or [specimen] key."""
    with pytest.raises(SceneFileError, match=match):
        scene_from_data(scene_data_with(base, changes))


@pytest.mark.parametrize(
    ("base", "contact", "match"),
    [
        (FLAT, {"frame": "shared"}, r"has no meaning on a 'flat' specimen"),
        (ARC, {"frame": "shared", "sliding": False}, r"sliding is off"),
        (ARC, {"frame": "turned"}, r"got 'turned'"),
    ],
)
def test_bad_frames_of_a_scene_made_in_python_are_refused_when_built(base, contact, match):
    scene = scene_from_data(base)
    scene = attrs.evolve(scene, contact=attrs.evolve(scene.contact, **contact))
    with pytest.raises(SceneFileError, match=match):
        build(scene)


def test_the_wear_history_checks_its_frame():
    simulation = build(scene_from_data(scene_data_with(WEAR, {"contact__pairs": 11})))[0]
    laws = {"upper": EnergyWear(1e-5), "lower": EnergyWear(2e-5)}
    with pytest.raises(WearInputError, match=r"must be 'local' .* got 'turned'"):
        WearSimulation(simulation, laws, 10, sliding=True, frame="turned")
    with pytest.raises(WearInputError, match=r"frame = 'shared' .*sliding is off"):
        WearSimulation(simulation, laws, 10, frame="shared")


def _run_file(tmp_path, capsys, data) -> tuple[dict, dict, dict]:
    """``data`` through ``fretbem run``: each step's (p, q) rows and summary entry, and the
    summary's scene facts."""
    path, out = tmp_path / "scene.toml", tmp_path / "out"
    path.write_text(_toml(data))
    code = main(["run", str(path), "--out", str(out), "--no-figures", "--no-vtk", "--quiet"])
    assert code == 0, capsys.readouterr().err
    rows: dict[str, list] = {}
    with open(out / "results.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            rows.setdefault(row["step"], []).append([float(row[k]) for k in ("p", "q")])
    summary = json.loads((out / "summary.json").read_text())
    steps = {s["step"]: s for s in summary["steps"]}
    return {k: np.array(v) for k, v in rows.items()}, steps, summary["scene"]


def _toml(data: dict) -> str:
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    return "\n".join(
        f"[{table}]\n" + "".join(f"{k} = {value(v)}\n" for k, v in keys.items())
        for table, keys in data.items()
    )


@pytest.mark.parametrize("frame", ["shared", "local"])
def test_the_scene_files_frame_gives_the_python_runs_numbers(tmp_path, capsys, frame):
    """examples/gross_sliding_arc.toml at 21 pairs with [contact] frame through fretbem run
    and run_sliding(frame=...) from Python: the same pressures and shears (results.csv's
    digits). The frame matters: Q / f P at the block is 0.99958 in the shared frame (the
    loads along the pairs' own frame), 0.99630 in the local ones (the pressure's centre
    ahead of the pad's axis tilts its pairs' normals; tests/validation/test_sliding_arc.py;
    measured, both ways)."""
    data = scene_data_with(ARC, {**SMALL, "contact__frame": frame})
    rows, steps, scene = _run_file(tmp_path, capsys, data)
    assert scene["frame"] == frame  # summary.json says which frame the run used
    simulation = build(scene_from_data(data))[0]
    sliding = run_sliding(simulation, note=None, frame=frame)
    for step in sliding.steps:
        p, q = rows[step.name].T
        assert np.abs(p - step.pressure).max() < 1e-9 * step.pressure.max()
        assert np.abs(q - step.shear).max() < 1e-9 * step.pressure.max()
    for name, sign in (("slide", 1.0), ("back", -1.0)):
        ratio = steps[name]["Q"] / (sign * 0.3 * steps[name]["P"])
        assert ratio == pytest.approx(0.99958 if frame == "shared" else 0.99630, abs=1e-4)


def test_the_default_frame_is_local():
    """Without the key a scene slides each pair in its own frame, as run_sliding does
    (examples/gross_sliding_arc.toml writes it out)."""
    assert ARC["contact"]["frame"] == "local"
    scene = scene_from_data(scene_data_with(ARC, {**SMALL, "contact__frame": None}))
    assert scene.contact.frame is None and scene.contact.sliding_frame == "local"
    shared = scene_from_data(scene_data_with(ARC, {**SMALL, "contact__frame": "shared"}))
    assert shared.contact.sliding_frame == "shared"


def test_wear_along_an_arc_takes_the_scene_files_frame():
    """examples/fretting_wear_sliding_arc.toml (11 pairs, 20 cycles) with frame = 'shared'
    through the run pipeline and from Python: the same worn depths to round-off; the
    local frame's differ (each pair's depth is a gap along its own normal)."""
    changes = {"contact__pairs": 11, "wear__cycles": 20, "wear__output": [10]}
    laws = {"upper": EnergyWear(1e-5), "lower": EnergyWear(2e-5)}
    depths = {}
    for frame in ("shared", "local"):
        data = scene_data_with(WEAR, {**changes, "contact__frame": frame})
        scene = scene_from_data(data)
        from_file = run_scene(scene).wear.result.final.profile
        simulation = build(scene)[0]
        control = JumpControl(relative_change=WEAR["wear"]["relative_change"])
        wear = WearSimulation(simulation, laws, 20, ("A", "B", "C"), control, (10,),
                              sliding=True, frame=frame)  # fmt: skip
        from_python = run_wear(wear).final.profile
        for body in ("upper", "lower"):
            assert np.array_equal(from_file.depth(body), from_python.depth(body))
        depths[frame] = from_file.depth("lower")
    assert not np.array_equal(depths["shared"], depths["local"])
