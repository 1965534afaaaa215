"""[specimen] shape = "groove": a concave specimen face, from the scene file and from Python.

The groove draws its own arc (radius R about (0, R)) over the pad's zone; every scene that
cannot be a pad in a groove is refused with the key to change; a groove scene runs through
``fretbem run`` with both body models and both families, its pressure against Hertz with
1/R* = 1/R_pad - 1/R_groove (conforming contact).
"""

from __future__ import annotations

import math
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.geometry.shapes import CylinderPad, GrooveSpecimen, NurbsShape, ShapeError
from fretbem.scenes.builder import build, hertz, zone_half_width
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.spec import SceneFileError
from fretbem.simulation import run
from fretbem.testing.scenes import scene_data_with

ROOT = Path(__file__).resolve().parents[3]
BASE = tomllib.loads((ROOT / "examples" / "gross_sliding_groove.toml").read_text())
#: the example without sliding: a pad R 40 pressed in a groove R 70, then sheared
PRESSED = {"contact__sliding": None, "load__delta": None, "load__Q": [0.0, 20.0],
           "load__steps": ["press", "shear"], "load__increments": [1, 4]}  # fmt: skip


def _scene(**changes):
    return scene_data_with(BASE, {**PRESSED, **changes})


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"contact__pairing": None}, r"shape = 'groove'.*pairing = 'node-to-node'; set \[contact\] "
                                     r"pairing = 'node-to-segment'"),
        ({"pad__radius": 70.0}, r"\[specimen\] radius = 70 mm: a groove must be wider than the "
                                r"cylinder pad .*\[pad\] radius = 70 mm.*make \[specimen\] radius "
                                r"larger"),
        ({"pad__radius": 90.0}, r"\[pad\] radius = 90 mm"),
        ({"specimen__radius": None}, r"a 'groove' specimen needs 'radius'"),
        ({"pad__shape": "rounded-flat", "pad__radius": None, "pad__flat": 0.5,
          "pad__edge_radius": 5.0}, r"rounded-flat pad's flat cannot sit in a concave groove"),
        ({"specimen__support": "ends"}, r"support = 'ends' .* 'groove' specimen has sides"),
        ({"specimen__width": 150.0}, r"groove of radius 70 mm cannot be 150 mm wide"),
        ({"specimen__length": 20.0}, r"\[specimen\] length does not apply to a 'groove'"),
        ({"specimen__radius": -70.0}, r"radius"),
    ],
)  # fmt: skip
def test_scenes_that_are_not_a_pad_in_a_groove_are_refused(changes, match):
    with pytest.raises(SceneFileError, match=match):
        scene_from_data(_scene(**changes))


def test_a_cylinder_specimen_with_ends_support_is_refused_too():
    data = _scene(specimen__shape="cylinder", specimen__support="ends", pad__radius=70.0)
    with pytest.raises(SceneFileError, match=r"'cylinder' specimen has sides, not ends"):
        scene_from_data(data)


def test_a_scene_made_in_python_is_checked_when_built():
    """A Scene record made in Python (no file reading): node-to-node pairing and a pad as
    wide as the groove are refused by build() with the reader's messages."""
    scene = scene_from_data(_scene())
    nodes = attrs.evolve(scene, contact=attrs.evolve(scene.contact, pairing="node-to-node"))
    with pytest.raises(SceneFileError, match=r"pairing = 'node-to-node'; set \[contact\]"):
        build(nodes)
    equal = attrs.evolve(scene.pad, shape=CylinderPad(70.0, 6.5, 16.25))
    with pytest.raises(SceneFileError, match=r"a groove must be wider than the cylinder pad"):
        build(attrs.evolve(scene, pad=equal))


def test_a_drawn_pad_that_cuts_into_the_groove_is_refused_when_built():
    """A nurbs pad flatter than the groove (R 100 in R 70) touches it off its lowest point:
    refused naming the depth and where; the same pad drawn at R 40 builds."""
    scene = scene_from_data(_scene())
    zone = zone_half_width(scene)
    for radius, fits in ((100.0, False), (40.0, True)):
        drawn = NurbsShape(CylinderPad(radius, 6.5, 16.25).boundary(zone).segments)
        pad = attrs.evolve(scene.pad, shape=drawn)
        bad = attrs.evolve(scene, pad=pad, contact=attrs.evolve(scene.contact, zone_width=zone))
        if fits:
            build(bad)
            continue
        with pytest.raises(ShapeError, match=r"cuts into the groove .* by 0\.0\d+ mm at x = "):
            build(bad)


def test_the_groove_is_a_concave_arc_over_the_pads_zone():
    groove = GrooveSpecimen(70.0, 14.0, 10.0)
    assert groove.curvature == -1.0 / 70.0
    face = CylinderPad(40.0, 6.5, 16.25).face(0.8)
    boundary = groove.boundary(face, 0.8)
    assert [s.tag for s in boundary.segments] == [
        "bottom", "side_right", "flank_right", "contact", "flank_left", "side_left",
    ]  # fmt: skip
    xi = np.linspace(0.0, 1.0, 33)
    for segment in boundary.segments[2:5]:
        points = segment.curve.points(xi)
        assert np.allclose(np.linalg.norm(points - [0.0, 70.0], axis=1), 70.0, atol=1e-12)
        assert np.all(np.diff(points[:, 0]) < 0)  # right to left: counterclockwise
    contact = boundary.segments[3].curve.points([0.0, 1.0])
    assert np.allclose(contact[:, 0], [0.8, -0.8], atol=1e-12)
    ends = [s.curve.points([0.0, 1.0]) for s in boundary.segments]
    for (_, end), (start, _) in zip(ends, ends[1:] + ends[:1], strict=True):
        assert np.allclose(end, start, atol=1e-12)  # a closed chain
    assert groove.height_at(7.0) == pytest.approx(70.0 - math.sqrt(70.0**2 - 49.0))


#: bodies large against the contact (a 26 mm wide pad, a 40 x 20 mm groove): the 6.5 mm
#: pad of the example bends under its load and is 1.3 % off Hertz pressed
LARGE = {"pad__width": 26.0, "specimen__width": 40.0, "specimen__height": 20.0}


@pytest.mark.parametrize(
    ("changes", "error"),
    [
        ({}, 0.003),  # measured 0.20 %
        ({"load__P": 160.0}, 0.0035),  # 0.26 %
        ({"contact__basis": "lagrange2"}, 0.032),  # 2.9 %: lagrange2 on curved faces
        ({"specimen__model": "half-plane"}, 0.002),  # 0.13 %
        ({"pad__model": "half-plane", "specimen__model": "half-plane"}, 0.0015),  # 0.087 %
    ],
)
def test_a_pad_pressed_in_a_groove_has_the_conforming_hertz_pressure(changes, error):
    """61 pairs: the pressure within ``error`` of p0 of Hertz's with R* = 1/(1/40 - 1/70) =
    93.3 mm (a = 0.537 mm at P = 100 N/mm), for BEM and half-plane bodies and both
    families; the closed form the run is checked against is Mindlin-Deresiewicz's."""
    scene = scene_from_data(_scene(**LARGE, **changes))
    contact = hertz(scene)
    assert contact.effective_radius == pytest.approx(1.0 / (1.0 / 40.0 - 1.0 / 70.0))
    simulation, reason = build(scene)
    assert reason is None and type(simulation.reference).__name__ == "MindlinDeresiewicz"
    step = run(simulation).steps[0]
    x = simulation.pair.pairing().points[:, 0]
    p = step.pressure
    assert abs(np.sum(x * p) / np.sum(p)) < 1e-9
    assert np.max(np.abs(p - contact.pressure(x))) < error * contact.peak_pressure
