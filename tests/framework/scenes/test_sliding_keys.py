"""[contact] sliding and track_width: each bad combination refused with the key to change,
the track built from the history, and a slide off the track refused through fretbem run."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import tomllib

from fretbem.accuracy.modes import Accuracy
from fretbem.app.cli import main
from fretbem.errors import InputError
from fretbem.pipeline import run_simulation
from fretbem.scenes.builder import build, zone_half_width
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.spec import SceneFileError
from fretbem.scenes.track import TRACK_DENSITY, track_half_width
from fretbem.testing.scenes import scene_data_with

ROOT = Path(__file__).resolve().parents[3]
BASE = tomllib.loads((ROOT / "examples" / "gross_sliding.toml").read_text())


def _scene(**changes):
    return scene_data_with(BASE, changes)


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"contact__pairing": "node-to-node"}, r"sliding = true .*set \[contact\] pairing = "
                                               r"'node-to-segment'"),
        ({"contact__pairing": None}, r"pairing = 'node-to-node'"),
        ({"contact__sliding": False, "contact__track_width": 3.0}, r"track_width .*sliding is off"),
        ({"contact__track_width": -1.0}, r"track_width must be > 0"),
        ({"contact__sliding": "yes"}, r"\[contact\] sliding"),
        ({"contact__mesh": "adaptive", "contact__pairs": None}, r"sliding = true needs mesh = "
                                                                 r"'fixed'"),
    ],
)  # fmt: skip
def test_bad_sliding_keys_are_refused(changes, match):
    with pytest.raises(SceneFileError, match=match):
        scene_from_data(_scene(**changes))


def _cylinder(**changes):
    cylinder = {
        "specimen__shape": "cylinder", "specimen__length": None, "specimen__thickness": None,
        "specimen__radius": 70.0, "specimen__width": 12.0, "specimen__height": 10.0,
    }  # fmt: skip
    return _scene(**{**cylinder, **changes})


def test_a_curved_track_on_half_plane_bodies_is_refused():
    """A cylinder specimen's track is an arc the pad turns along: half-plane bodies (the
    example's) cannot turn; the key and both fixes are named."""
    with pytest.raises(
        SceneFileError,
        match=r"\[pad\] model = 'half-plane'.*\[specimen\] "
        r"model = 'bem'.*\[specimen\] shape = 'flat'",
    ):
        build(scene_from_data(_cylinder()))
    with pytest.raises(SceneFileError, match=r"\[specimen\] model = 'half-plane'"):
        build(scene_from_data(_cylinder(pad__model="bem")))


def test_the_pads_stresses_on_an_arc_are_refused():
    """The pad turns along the arc: its fields are in its own axes, so [stress] on it is
    refused at reading (and by the evaluator from Python)."""
    data = _cylinder(pad__model="bem", specimen__model="bem", stress__body="upper")
    with pytest.raises(SceneFileError, match=r"\[stress\] body = 'upper'.*body = 'lower'"):
        build(scene_from_data(data))


def test_a_cylinder_track_past_the_specimen_is_refused():
    data = _cylinder(pad__model="bem", specimen__model="bem", specimen__width=5.0)
    with pytest.raises(SceneFileError, match=r"half-width 2.5 mm.*lengthen \[specimen\] width"):
        build(scene_from_data(data))


def test_a_track_past_the_specimen_is_refused():
    with pytest.raises(SceneFileError, match=r"lengthen \[specimen\] length.*track_width"):
        build(scene_from_data(_scene(specimen__length=6.0)))


def test_the_track_covers_the_zone_and_the_largest_delta():
    """Default: zone + max |delta| (2.8 mm), meshed TRACK_DENSITY times as finely as the
    pad's zone; an explicit track_width wins; faces stay independent per [specimen]."""
    scene = scene_from_data(BASE)
    zone = zone_half_width(scene)
    assert track_half_width(scene, zone) == pytest.approx(zone + 2.8)
    simulation, _ = build(scene)
    pad = simulation.pair.upper.contact_face("contact").n_nodes
    track = simulation.pair.lower.contact_face("contact").n_nodes
    assert track / pad == pytest.approx(TRACK_DENSITY * (zone + 2.8) / zone, rel=0.05)
    wide = scene_from_data(_scene(contact__track_width=4.0))
    assert track_half_width(wide, zone) == 4.0
    # [specimen] pairs or elements count the zone, as on any scene: the track keeps that
    # density along the whole slide (100 elements over 2 zone: 100 (zone + 2.8) / zone)
    own = scene_from_data(_scene(specimen__elements=100))
    elements = math.ceil(100 * (zone + 2.8) / zone)
    assert build(own)[0].pair.lower.contact_face("contact").n_nodes == elements + 2
    pairs = scene_from_data(_scene(specimen__pairs=41))
    assert (
        build(pairs)[0].pair.lower.contact_face("contact").n_nodes
        == math.ceil(39 * (zone + 2.8) / zone) + 2
    )


def test_sliding_refuses_implicit_wear_fatigue_without_map_and_the_adaptive_mode():
    simulation, _ = build(scene_from_data(BASE))
    implicit = {"pad": 1e-5, "specimen": 1e-5, "cycles": 10, "scheme": "implicit"}
    with pytest.raises(InputError, match=r"scheme = 'implicit' is not available with finite"):
        run_simulation(simulation, sliding=True, extras={"wear": implicit})
    with pytest.raises(InputError, match=r"\[fatigue\] on a finite-sliding run .*map_x"):
        run_simulation(simulation, sliding=True, extras={"fatigue": {"material": "x"}})
    with pytest.raises(InputError, match=r"sliding = true needs mesh = 'fixed'"):
        run_simulation(simulation, sliding=True, mode=Accuracy(mesh="adaptive"))


def test_a_slide_off_the_track_is_refused_by_fretbem_run(tmp_path, capsys):
    """track_width shorter than the slide: exit 2, one line naming [contact] track_width."""
    path = tmp_path / "short.toml"
    text = (ROOT / "examples" / "gross_sliding.toml").read_text()
    text = text.replace("\nsliding = true", "\ntrack_width = 1.5\nsliding = true", 1)
    text = text.replace("increments = [1, 24, 24]", "increments = [1, 12, 1]")
    text = text.replace('steps = ["press", "slide", "back"]', 'steps = ["press", "slide", "b"]')
    path.write_text(text)
    code = main(["run", str(path), "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2
    assert "slid past the end of the other face" in err and "[contact] track_width" in err
    assert "Traceback" not in err


def test_bem_bodies_slide_from_the_scene_file(tmp_path, capsys):
    """examples/gross_sliding_bem.toml through fretbem run (at 21 pairs): finite bodies
    slide, Q = f P both ways from the files, the pressure's centre ahead of the pad's
    block in the sense of Q less the bodies' give (about 0.134 - 0.026 mm; the physics is
    checked in tests/validation/test_sliding_bem.py)."""
    rows, steps = _slide_and_back(tmp_path, capsys, "gross_sliding_bem.toml")
    for name, sign, block in (("slide", 1.0, 2.8), ("back", -1.0, 0.0)):
        x, p, q = np.array(rows[name]).T
        assert steps[name]["Q"] == pytest.approx(sign * 0.3 * steps[name]["P"], rel=1e-3)
        assert np.max(np.abs(q - sign * 0.3 * p)) < 1e-9 * p.max()
        centre = np.sum(x * p) / np.sum(p)
        assert 0.08 < sign * (centre - block) < 0.14


@pytest.mark.parametrize(
    ("example", "slide"),
    [("gross_sliding_arc.toml", 2.0), ("gross_sliding_groove.toml", 3.0)],
)
def test_bem_bodies_slide_along_an_arc_from_the_scene_file(tmp_path, capsys, example, slide):
    """examples/gross_sliding_arc.toml (convex specimen) and gross_sliding_groove.toml
    (concave) through fretbem run (at 21 pairs): the pad slides ``slide`` mm along the arc
    and back, turning with it; Q = f P both ways in the local frame, q = f p at every
    pair, the pressure centred within 0.15 mm of the block (the physics is checked in
    tests/validation/test_sliding_arc.py). Each pair in the arc's own frame, the pressure
    off the pad's axis has a share along Q: Q / f P at the block 0.9964 on the narrow
    reference pad (its contact 0.06 mm ahead on the convex arc), 1.0080 in the groove, whose
    normals tilt the other way (measured)."""
    rows, steps = _slide_and_back(tmp_path, capsys, example)
    for name, sign, block in (("slide", 1.0, slide), ("back", -1.0, 0.0)):
        x, p, q = np.array(rows[name]).T
        ratio = steps[name]["Q"] / (sign * 0.3 * steps[name]["P"])
        assert ratio == pytest.approx(0.9963 if "arc" in example else 1.0080, abs=1e-3)
        assert np.max(np.abs(q - sign * 0.3 * p)) < 1e-9 * p.max()
        centre = np.sum(x * p) / np.sum(p)
        assert abs(centre - block) < 0.15


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"specimen__model": "half-plane"}, r"on a groove specimen .*\[specimen\] model = "
                                            r"'half-plane'"),
        ({"pad__model": "half-plane"}, r"\[pad\] model = 'half-plane'"),
        ({"stress__body": "upper", "stress__points": [[0.0, 1.0]]},
         r"\[stress\] body = 'upper': the pad slides along the groove specimen's arc"),
        ({"contact__track_width": 7.5}, r"track .*half-width 7\.5 mm.*half-width 7 mm"),
    ],
)  # fmt: skip
def test_bad_sliding_in_a_groove_is_refused(changes, match):
    groove = tomllib.loads((ROOT / "examples" / "gross_sliding_groove.toml").read_text())
    data = scene_data_with(groove, changes)
    with pytest.raises(SceneFileError, match=match):
        build(scene_from_data(data))


def _slide_and_back(tmp_path, capsys, example: str) -> tuple[dict, dict]:
    """Run ``examples/<example>`` at 21 pairs through ``fretbem run``: each step's (x, p, q)
    rows from results.csv and its summary.json entry."""
    out = tmp_path / "out"
    code = main(["run", str(ROOT / "examples" / example), "--out", str(out), "--pairs", "21",
                 "--no-figures", "--no-vtk", "--quiet"])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    rows: dict[str, list] = {}
    with open(out / "results.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            rows.setdefault(row["step"], []).append([float(row[k]) for k in ("x", "p", "q")])
    summary = json.loads((out / "summary.json").read_text())
    return rows, {s["step"]: s for s in summary["steps"]}
