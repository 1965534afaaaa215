"""Scene files: both examples read, old files still run, command-line overrides, bad files."""

from pathlib import Path

import numpy as np
import pytest

from fretbem.scenes.builder import build
from fretbem.scenes.file import SceneFileError, load_scene
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "cattaneo_mindlin.toml"
ROUND_ONE = ROOT / "tests" / "framework" / "data" / "cattaneo_mindlin_round1.toml"


@pytest.mark.parametrize("path", [EXAMPLE, ROUND_ONE])
def test_example_is_the_reference_scene(path):
    """The example (and its round-1 form) give the reference scene's unknowns exactly."""
    simulation, reason = build(load_scene(path, pairs=31))
    assert reason is None
    ours, reference = run(simulation), run(cattaneo_mindlin(pairs=31))
    for a, b in zip(ours.steps, reference.steps, strict=True):
        np.testing.assert_array_equal(a.unknowns, b.unknowns)


def test_round_one_file_is_marked():
    assert load_scene(ROUND_ONE).legacy and not load_scene(EXAMPLE).legacy


def test_overrides_replace_file_values():
    """--basis and --pairs override the file."""
    scene = load_scene(EXAMPLE, basis="lagrange2", pairs=121)
    assert (scene.contact.basis, scene.contact.pairs) == ("lagrange2", 121)


def test_unreadable_file(tmp_path):
    """A missing file, invalid TOML or a binary file is an error naming the file."""
    with pytest.raises(SceneFileError, match="cannot read"):
        load_scene(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[contact\nbasis = 1")
    with pytest.raises(SceneFileError, match="not valid TOML"):
        load_scene(bad)
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    with pytest.raises(SceneFileError, match="not a text file"):
        load_scene(binary)
    typo = tmp_path / "typo.toml"
    typo.write_text("[contact]\npair = 61\n")
    with pytest.raises(SceneFileError, match=r"typo.toml: unknown key \['pair'\] in \[contact\]"):
        load_scene(typo)
