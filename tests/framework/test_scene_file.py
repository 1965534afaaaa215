"""Scene files: the documented keys, and a clear error for every bad input."""

import attrs
import pytest

from fretbem.scene_file import SceneFileError, load_scene, scene_from_dict
from fretbem.scenes import CattaneoMindlinScene

EXAMPLE = "examples/cattaneo_mindlin.toml"


def test_example_is_the_reference_scene():
    """examples/cattaneo_mindlin.toml describes exactly the default reference scene."""
    assert attrs.asdict(load_scene(EXAMPLE)) == attrs.asdict(CattaneoMindlinScene())


def test_overrides_replace_file_values():
    """--basis and --pairs override the file."""
    scene = load_scene(EXAMPLE, basis="lagrange2", pairs=121)
    assert (scene.basis, scene.pairs) == ("lagrange2", 121)


def test_per_body_material():
    """[material.lower] overrides [material] for one body only."""
    scene = scene_from_dict({"material": {"E": 1000.0, "nu": 0.3, "lower": {"E": 2000.0}}})
    assert (scene.E_upper, scene.E_lower, scene.nu_lower) == (1000.0, 2000.0, 0.3)


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"scene": {"pair": 61}}, r"unknown key \['pair'\] in \[scene\]"),
        ({"geometry": {"radius": float("nan")}}, r"\[geometry\] radius must be a finite"),
        ({"load": {"Q": [0.0, float("inf")]}}, r"\[load\] Q\[1\] must be a finite"),
        ({"contact": {"friction": "0.3"}}, r"\[contact\] friction must be int or float"),
        ({"scene": {"pairs": True}}, r"\[scene\] pairs must be int"),
        ({"loads": {}}, r"unknown key \['loads'\] in the scene file"),
        ({"material": {"upper": {"G": 1.0}}}, r"unknown key \['G'\] in \[material.upper\]"),
        ({"load": {"Q": [0.0, 1.0], "steps": ["A"]}}, "one name per value of Q"),
        ({"geometry": {"lower": "cone"}}, "invalid scene"),
    ],
)
def test_bad_scene_files(data, message):
    """Typos, non-finite numbers and wrong types are errors naming the key."""
    with pytest.raises(SceneFileError, match=message):
        scene_from_dict(data)


def test_unreadable_file(tmp_path):
    """A missing file or invalid TOML is an error naming the file."""
    with pytest.raises(SceneFileError, match="cannot read"):
        load_scene(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[scene\nbasis = 1")
    with pytest.raises(SceneFileError, match="not valid TOML"):
        load_scene(bad)
