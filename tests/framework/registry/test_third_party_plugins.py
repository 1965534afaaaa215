"""A body model and a solver from a third party's package, named in a scene file.

examples/custom_plugins is registered for the test only: its folder and a throw-away
``.dist-info`` (the entry points pip would write) go on ``sys.path`` and are removed after,
so nothing is installed into the environment.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from fretbem import registry
from fretbem.app import cli

PLUGINS = Path(__file__).resolve().parents[3] / "examples" / "custom_plugins"

SCENE = """
[pad]
shape = "cylinder"
radius = {radius}
width = 4.0
height = 4.0
[pad.material]
E = 1.0e9          # a rigid pad: the Winkler closed form holds
nu = 0.3

[specimen]
shape = "flat"
length = 8.0
thickness = 4.0
model = "winkler"

[material]
E = 200000.0
nu = 0.3

[contact]
friction = 0.3
pairs = {pairs}
zone_width = {zone}
solver = "newton-lemke"

[load]
steps = ["A", "B"]
P = {load}
Q = [0.0, {tangential}]
"""


@pytest.fixture
def third_party(tmp_path):
    """examples/custom_plugins importable and its entry points registered, for one test."""
    info = tmp_path / "fretbem_winkler-0.1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fretbem-winkler\nVersion: 0.1.0\n")
    (info / "entry_points.txt").write_text(
        "[fretbem.bodies]\nwinkler = fretbem_winkler:WinklerModel\n\n"
        "[fretbem.solvers]\nnewton-lemke = fretbem_winkler:NewtonThenLemke\n"
    )
    sys.path[:0] = [str(PLUGINS), str(tmp_path)]
    registry.refresh()
    yield
    sys.path.remove(str(PLUGINS))
    sys.path.remove(str(tmp_path))
    sys.modules.pop("fretbem_winkler", None)
    registry.refresh()


def test_plugins_command_lists_them(third_party, capsys):
    assert cli.main(["plugins"]) == 0
    out = capsys.readouterr().out
    assert "winkler" in out and "fretbem-winkler 0.1.0" in out
    assert "newton-lemke" in out and "fretbem_winkler:NewtonThenLemke" in out


@pytest.mark.parametrize(("load", "radius", "pairs"), [(50.0, 50.0, 41), (200.0, 20.0, 61)])
def test_scene_file_runs_a_third_party_body_model_and_solver(
    third_party, tmp_path, load, radius, pairs
):
    """A rigid cylinder on a Winkler bed: a = (3 P R / (2 k))^(1/3), p = k (d - x^2 / 2R)."""
    stiffness = 200000.0 / (1 - 0.3**2) / 1.0  # E' / 1 mm
    a = (3 * load * radius / (2 * stiffness)) ** (1 / 3)
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE.format(radius=radius, pairs=pairs, zone=1.6 * a, load=load,
                                  tangential=0.5 * 0.3 * load))  # fmt: skip
    out = tmp_path / "out"
    assert cli.main(["run", str(scene), "--out", str(out), "--no-figures", "--no-vtk"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"][0]["integral_p"] == pytest.approx(load, rel=1e-3)
    rows = np.genfromtxt(out / "results.csv", delimiter=",", names=True, dtype=None,
                         encoding="utf-8")  # fmt: skip
    first = rows[rows["step"] == "A"]
    x, p = first["x"], first["p"]
    touching = x[p > 0]
    spacing = np.diff(np.sort(x)).max()
    assert abs(touching.max() - a) < spacing and abs(-touching.min() - a) < spacing
    delta = a**2 / (2 * radius)
    exact = np.maximum(stiffness * (delta - x**2 / (2 * radius)), 0.0)
    inside = np.abs(x) < 0.8 * a  # away from the edge, where the node spacing blurs it
    # measured 4e-5 and 3.6e-4 of the peak (trapezoidal node weights near the edge)
    assert np.max(np.abs(p[inside] - exact[inside])) < 2e-3 * exact.max()
