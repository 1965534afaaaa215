"""The two-body scene file: every key documented once, every bad input a named error."""

from pathlib import Path

import pytest
import tomllib

from fretbem.geometry.shapes import CylinderPad, FlatSpecimen, NurbsShape, RoundedFlatPad
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.spec import KEYS, SceneFileError, markdown_table

ROOT = Path(__file__).resolve().parents[3]


def read(name: str) -> dict:
    return tomllib.loads((ROOT / "examples" / name).read_text())


def test_docs_table_is_the_key_table():
    """docs/scene-format.md shows exactly the table generated from KEYS."""
    assert markdown_table() in (ROOT / "docs" / "scene-format.md").read_text()


def test_rig_example():
    scene = scene_from_data(read("fretting_rig.toml"))
    assert isinstance(scene.pad.shape, CylinderPad) and scene.pad.shape.radius == 70.0
    assert isinstance(scene.specimen.shape, FlatSpecimen) and scene.specimen.support == "ends"
    assert scene.load.bulk == (0.0, 90.0, 0.0, -90.0, 0.0)
    assert scene.load.P == (200.0,) * 5 and not scene.legacy


def test_round_one_file_is_translated():
    old = tomllib.loads((ROOT / "tests/framework/data/cattaneo_mindlin_round1.toml").read_text())
    scene = scene_from_data(old)
    new = scene_from_data(read("cattaneo_mindlin.toml"))
    for part in ("pad", "specimen"):
        old_body, new_body = getattr(scene, part), getattr(new, part)
        assert (old_body.shape, old_body.material, old_body.model, old_body.support) == (
            new_body.shape,
            new_body.material,
            new_body.model,
            new_body.support,
        )
    assert (scene.contact, scene.mesh, scene.load) == (new.contact, new.mesh, new.load)
    assert scene.legacy and scene.specimen.support == "clamped-bottom"
    assert scene.contact.pairs == 61 and scene.load.Q == (0.0, 18.0, 0.0, -18.0, 0.0)
    flat = scene_from_data({"geometry": {"lower": "flat", "width": 8.0, "height": 9.0}})
    assert flat.specimen.shape == FlatSpecimen(8.0, 9.0)
    per_body = scene_from_data({"material": {"E": 1000.0, "nu": 0.3, "lower": {"E": 2000.0}}})
    assert (per_body.pad.material.E, per_body.specimen.material.E) == (1000.0, 2000.0)


def test_scalars_broadcast_and_materials_override():
    scene = scene_from_data(
        {
            "pad": {"shape": "rounded-flat", "flat": 0.5, "edge_radius": 20.0, "width": 8.0,
                    "height": 8.0, "material": {"E": 200000.0, "nu": 0.3, "plane": "stress"}},
            "contact": {"zone_width": 1.0},
            "load": {"P": [100.0, 100.0, 50.0], "Q": 0.0, "increments": [1, 4, 2]},
        }
    )  # fmt: skip
    assert isinstance(scene.pad.shape, RoundedFlatPad) and scene.pad.material.plane_stress
    assert scene.specimen.material.E == 73400.0  # [material] default
    assert scene.load.steps == ("step1", "step2", "step3") and scene.load.Q == (0.0,) * 3
    assert scene.load.increments == (1, 4, 2)


def test_explicit_nurbs_segments():
    line = lambda tag, a, b: {"tag": tag, "degree": 1, "knots": [0, 0, 1, 1], "points": [a, b]}  # noqa: E731
    square = [line("bottom", [0, -1], [1, -1]), line("side", [1, -1], [1, 0]),
              line("contact", [1, 0], [0, 0]), line("side", [0, 0], [0, -1])]  # fmt: skip
    scene = scene_from_data({"specimen": {"shape": "nurbs", "segments": square}})
    assert isinstance(scene.specimen.shape, NurbsShape)
    assert [s.tag for s in scene.specimen.shape.segments] == ["bottom", "side", "contact", "side"]


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"pad": {"radius": float("nan")}}, r"\[pad\] radius must be a finite"),
        ({"pad": {"shape": "cone"}}, r"\[pad\] shape must be one of"),
        ({"pad": {"length": 3.0}}, r"unknown key \['length'\] in \[pad\]"),
        ({"specimen": {"shape": "flat", "radius": 3.0}}, "radius does not apply to a 'flat'"),
        (
            {"specimen": {"model": "fem"}},
            (
                r"\[specimen\] model: unknown body model 'fem'; "
                r"installed body models: 'bem', 'half-plane'"
            ),
        ),
        ({"contact": {"solver": "cg"}}, r"\[contact\] solver: unknown contact solver 'cg'"),
        ({"contact": {"law": "tresca"}}, r"\[contact\] law: unknown contact law 'tresca'"),
        ({"specimen": {"support": "glued"}}, r"support must be one of"),
        ({"pad": {"material": {"plane": "both"}}}, "plane must be 'strain' or 'stress'"),
        ({"material": {"nu": 0.7}}, "Poisson"),
        ({"contact": {"pairs": 0}}, "pairs must be >= 1"),
        ({"contact": {"friction": 0.0}}, "friction must be > 0"),
        ({"contact": {"friction": "0.3"}}, r"\[contact\] friction must be an integer or a number"),
        ({"load": {"steps": ["A", "A"], "Q": [0.0, 1.0]}}, "used twice"),
        ({"load": {"steps": ["A", "B"], "Q": [0.0, 1.0, 2.0]}}, "3 values for 2 steps"),
        ({"load": {"bulk": [0.0, float("inf")]}}, r"\[load\] bulk\[1\] must be a finite"),
        ({"load": {"increments": [1, 0]}}, "increments must be >= 1"),
        ({"loads": {}}, r"unknown key \['loads'\] in the scene file"),
        ({"pad": {"shape": "nurbs"}}, r"needs \[\[pad.segments\]\]"),
        ({"pad": {"shape": "rounded-flat", "flat": 1.0}}, "needs 'edge_radius'"),
        ({"pad": {"width": 200.0}}, "width < 2 radius"),
        ({"scene": {"pair": 61}}, r"unknown key \['pair'\] in \[scene\].*round-1 format"),
        ({"scene": {}, "geometry": {"lower": "cone"}}, "lower must be 'arc' or 'flat'"),
    ],
)
def test_bad_scene_files(data, message):
    with pytest.raises(SceneFileError, match=message):
        scene_from_data(data)


def test_every_key_has_unit_and_meaning():
    for key in KEYS:
        assert key.meaning, key
        assert key.unit in (
            "",
            "mm",
            "MPa",
            "N/mm",
            "degrees",
            "N mm/mm",
            "rad",
            "N mm/mm per rad",
        ), key
