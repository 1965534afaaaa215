"""A pad turned by the pairing (``NodeToSegmentPair.turn``, the pad slid along an arc) keeps
its own axes: its response, tractions and block are those of the pad as drawn, seen through
the turned pair frame. Turning the whole reference scene (the pad by the pairing, the
specimen drawn turned) must give the unturned scene's tractions and loads."""

from __future__ import annotations

import math
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.geometry.boundary import Segment
from fretbem.geometry.shapes import NurbsShape
from fretbem.scenes import builder
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import run
from fretbem.sliding.track import Track

ROOT = Path(__file__).resolve().parents[3]

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
        # M about the pad's pivot, which turns with it: the unturned pad's (h Q = 325)
        assert abs(one.moment - other.moment) < MOMENT * abs(angle) / 0.05
    assert abs(plain.steps[1].moment - 16.25 * 20.0) < 0.05 * 16.25 * 20.0


#: M of the whole scene turned against the unturned one's at 0.05 rad, N mm/mm (measured
#: 3.7e-6 at 0.05 rad and 1.5e-5 at -0.2, of M = 324.4; M left about the global frame's
#: pivot would differ by P times the pivot's shift, 100 x 16.25 x 0.05 = 81)
MOMENT = 1e-5


def test_a_turned_pad_carries_its_pivot_and_cannot_rotate():
    """The pivot is the pad's: found in its own axes (the placement undone), on its block's
    line above its first contact; a rotating block on a turned pad is refused."""
    from fretbem.contact import rotation
    from fretbem.contact.rotation import RotationError

    scene = scene_from_data(DATA)
    simulation, _ = builder.build(scene)
    drawn = simulation.pair.placed("upper")
    turn = np.array([[math.cos(0.05), -math.sin(0.05)], [math.sin(0.05), math.cos(0.05)]])
    moved = attrs.evolve(simulation.pair, turn=0.05, pivot=CENTRE, offset=[0.2, 0.0])
    placed = moved.placed("upper")
    assert np.allclose(placed, CENTRE + (drawn - CENTRE) @ turn.T + [0.2, 0.0], atol=1e-12)
    assert np.allclose(rotation.in_pad_axes(moved, placed), drawn, atol=1e-12)
    # the pad slid 1 mm along the arc of examples/gross_sliding_arc.toml (its specimen's
    # track covers it), its nodes the pairs: its lowest node under its pivot
    data = tomllib.loads((ROOT / "examples" / "gross_sliding_arc.toml").read_text())
    data["contact"]["pairs"] = 21
    sliding, _ = builder.build(scene_from_data(data))
    pair = Track.of(sliding.pair).placed(sliding.pair, 1.0)
    assert pair.slave_side() == "upper" and pair.turn == pytest.approx(-1.0 / 70.0)
    problem = pair.condensed()
    assert np.allclose(rotation.pivot(problem), [0.0, 16.25], atol=1e-9)
    with pytest.raises(RotationError, match=r"the pairing turns the pad .*turn = -0\.01429"):
        rotation.rotating(problem, rotation.pivot(problem))
