"""A pad turned by the pairing (``NodeToSegmentPair.turn``, the pad slid along an arc) keeps
its own axes: its response, tractions and block are those of the pad as drawn, seen through
the turned pair frame. Turning the whole reference scene (the pad by the pairing, the
specimen drawn turned) must give the unturned scene's tractions and loads."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

from fretbem.geometry.boundary import Segment
from fretbem.geometry.shapes import NurbsShape
from fretbem.scenes import builder
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import run

DATA = {
    "pad": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25},
    "specimen": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": 0.3, "pairs": 31, "pairing": "node-to-segment"},
    "load": {"steps": ["press", "shear"], "P": 100.0, "Q": [0.0, 20.0], "increments": [1, 3]},
}
CENTRE = np.array([0.0, -70.0])


def _turned_scene(scene, angle: float):
    """``scene`` with its specimen drawn turned by ``angle`` about the arc's centre."""
    zone = builder.zone_half_width(scene)
    boundary = builder._specimen_boundary(scene, builder._pad_face(scene, zone, True), zone)
    turn = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])

    def turned(curve):
        return attrs.evolve(curve, control_points=CENTRE + (curve.control_points - CENTRE) @ turn.T)

    segments = [Segment(s.tag, turned(s.curve)) for s in boundary.segments]
    return attrs.evolve(
        scene,
        specimen=attrs.evolve(scene.specimen, shape=NurbsShape(segments)),
        contact=attrs.evolve(scene.contact, zone_width=zone),
    )


@pytest.mark.parametrize("angle", [0.05, pytest.param(-0.2, marks=pytest.mark.slow)])
def test_the_whole_scene_turned_gives_the_same_contact(angle):
    """The pad turned by the pairing on the specimen drawn turned: p and q within 4e-6 p0
    of the unturned scene's (measured 1.9e-6 at 0.1 rad, linear in the angle: the turned
    specimen's BEM response itself differs by 2.6e-5 of its size), P and Q in the turned
    frame to 1e-8; a frame or a block left in the wrong axes errs by the angle (5 %)."""
    scene = scene_from_data(DATA)
    simulation, _ = builder.build(scene)
    plain = run(simulation)
    turned, _ = builder.build(_turned_scene(scene, angle))
    pair = attrs.evolve(turned.pair, turn=angle, pivot=CENTRE)
    result = run(attrs.evolve(turned, pair=pair, reference=None))
    p0 = float(np.max(plain.steps[0].pressure))
    normal = pair.pairing().normals[0]
    assert np.allclose(normal, [-math.sin(angle), math.cos(angle)], atol=1e-12)
    for one, other in zip(plain.steps, result.steps, strict=True):
        assert np.max(np.abs(one.pressure - other.pressure)) < 4e-6 * p0 * abs(angle) / 0.1
        assert np.max(np.abs(one.shear - other.shear)) < 4e-6 * p0 * abs(angle) / 0.1
        assert np.allclose(one.resultant, other.resultant, rtol=1e-8, atol=1e-8 * 100.0)
        # the pad's block, in its own axes, moves as the unturned pad's
        assert np.allclose(one.pair_unknowns.block("upper"), other.pair_unknowns.block("upper"),
                           rtol=0.0, atol=2e-5 * abs(angle))  # fmt: skip
