"""Stress lines and points at the contact edges: x = "trailing-edge" / "leading-edge", with
offsets in units of the contact half-width a."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fretbem.pipeline import run_scene
from fretbem.scenes.file import load_scene
from fretbem.stress.edges import EdgePosition, contact_half_width, parse_position
from fretbem.stress.errors import StressRequestError
from fretbem.stress.request import stress_request_from_dict

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "cattaneo_mindlin.toml"


@pytest.fixture(scope="module")
def rig_run():
    """The reference scene at 21 pairs (a Hertz closed form)."""
    return run_scene(load_scene(EXAMPLE, pairs=21))


@pytest.mark.parametrize(
    ("text", "edge", "offset"),
    [
        ("trailing-edge", "trailing-edge", 0.0),
        ("leading-edge", "leading-edge", 0.0),
        ("trailing-edge + 0.05a", "trailing-edge", 0.05),
        ("leading-edge-0.1a", "leading-edge", -0.1),
        ("trailing-edge - 2.5e-2 a", "trailing-edge", -0.025),
    ],
)
def test_edge_names_parse(text, edge, offset):
    position = parse_position(text)
    assert position == EdgePosition(edge, pytest.approx(offset))
    sign = -1.0 if edge == "trailing-edge" else 1.0
    assert position.resolve(0.5) == pytest.approx((sign + offset) * 0.5)
    assert position.resolve(0.5, centre=0.1) == pytest.approx(0.1 + (sign + offset) * 0.5)


@pytest.mark.parametrize("bad", ["trailing", "trailing-edge + 0.1", "edge", "leading-edge*2"])
def test_bad_positions_say_what_is_accepted(bad):
    with pytest.raises(StressRequestError, match=r"trailing-edge.*offset in units"):
        stress_request_from_dict({"line": {"x": bad, "depth": 1.0}})
    with pytest.raises(StressRequestError, match=r"\[stress\] points x"):
        stress_request_from_dict({"points": [[bad, 0.0]]})


def test_request_resolves_lines_and_points():
    request = stress_request_from_dict(
        {
            "line": [{"x": "trailing-edge", "depth": 1.0}, {"x": -0.3, "depth": 1.0}],
            "points": [["leading-edge - 0.1a", -0.05], [0.2, -0.1]],
        }
    )
    assert request.uses_edges
    placed = request.resolved(0.6)
    assert [line.x for line in placed.lines] == pytest.approx([-0.6, -0.3])
    assert np.allclose(placed.points, [[0.54, -0.05], [0.2, -0.1]])
    assert not placed.uses_edges
    numeric = stress_request_from_dict({"line": {"x": -0.3, "depth": 1.0}})
    assert not numeric.uses_edges and numeric.resolved(1.0) == numeric


def test_half_width_comes_from_hertz_or_the_computed_contact(rig_run):
    result = rig_run.result
    a, centre, source = contact_half_width(result)
    assert (a, centre, source) == (result.hertz()["a"], 0.0, "hertz")


def test_trailing_edge_line_is_written_at_minus_a(rig_run, tmp_path):
    from fretbem.stress.run import run_stress_request

    request = stress_request_from_dict(
        {"steps": ["B"], "figures": False, "vtk": False,
         "line": {"x": "trailing-edge + 0.1a", "depth": 0.5, "n": 4}}
    )  # fmt: skip
    written = run_stress_request(rig_run.result, request, tmp_path)
    rows = written["line_0"].read_text().splitlines()[1:]
    a = rig_run.result.hertz()["a"]
    assert float(rows[0].split(",")[1]) == pytest.approx(-0.9 * a, rel=1e-8)
