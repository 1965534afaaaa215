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


def test_a_turned_pad_carries_its_pivot():
    """The pivot is the pad's: found in its own axes (the placement undone), on its block's
    line above its first contact."""
    from fretbem.contact import rotation

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
    height, reach = rotation.lever(problem)  # the zone about the contact in the pad's axes
    assert height == pytest.approx(16.25, abs=1e-9) and reach[0] < 0.0 < reach[1]


#: the block's rotation per case: a spring about the pivot on the block's line, and a
#: moment and an actuator's rotation about a pivot 5 mm above the contact (the body's own
#: rotation centre is on its top: the moment's shift to the pivot turns the specimen's force)
ROTATIONS = {
    "spring": ({"stiffness_rotation": 2.0e5}, {}),
    "moment": ({"pivot_height": 5.0}, {"moment": [0.0, 90.0]}),
    "rotation": ({"pivot_height": 5.0, "stiffness_rotation": 1.0e5}, {"rotation": [0.0, -1e-3]}),
}


@pytest.mark.parametrize("case", sorted(ROTATIONS))
def test_a_turned_pad_rotates_as_the_whole_scene_turned_back(case):
    """A rotating block on a turned pad (a pad slid along an arc): its tilt theta about
    its pivot is in its own axes, so with the specimen drawn turned by 0.05 rad the scene
    is the unturned one's: p and q within 2e-6 of p0 (measured 3.7e-7, the turned
    specimen's BEM response), P and Q to 1e-8, M to 1e-5 of h Q (measured 1.1e-8) and the
    tilt to 1e-5 of itself (2.9e-7), while the block turns by 1.6 to 2.8 mrad; the moment of
    the contact tractions the rotation record gives equals their moment by quadrature over
    the pad's face within 1e-6 of h Q (measured 3e-10; 0.17 with the specimen's force left
    in the global axes about the lower pivot)."""
    from fretbem.testing.sliding import traction_moment

    rig, load = ROTATIONS[case]
    data = {**DATA, "rig": rig, "load": {**DATA["load"], **load}}
    scene = scene_from_data(data)
    simulation, _ = builder.build(scene)  # the pairs on the pad's nodes, as when sliding
    simulation = attrs.evolve(simulation, pair=attrs.evolve(simulation.pair, slave="upper"))
    plain = run(simulation)
    angle = 0.05
    turned, _ = builder.build(_turned_scene(scene, angle))
    pair = attrs.evolve(turned.pair, turn=angle, pivot=CENTRE, slave="upper")
    spun = attrs.evolve(turned, pair=pair, reference=None, pivot=simulation.block_pivot())
    result = run(spun)
    p0 = float(np.max(plain.steps[0].pressure))
    moment = 16.25 * 20.0
    for one, other in zip(plain.steps, result.steps, strict=True):
        assert np.max(np.abs(one.pressure - other.pressure)) < 2e-6 * p0
        assert np.max(np.abs(one.shear - other.shear)) < 2e-6 * p0
        assert np.allclose(one.resultant, other.resultant, rtol=1e-8, atol=1e-8 * 100.0)
        assert abs(one.moment - other.moment) < 1e-5 * moment
        assert abs(one.tilt - other.tilt) <= 1e-5 * abs(one.tilt) + 1e-12  # pressed: 1e-14
        for sim, step in ((simulation, one), (spun, other)):
            problem = sim.prepare()
            balance = -problem.rotation.contact_moment(np.asarray(step.unknowns))
            assert abs(balance - traction_moment(step, sim.pair, sim.block_pivot())[0]) < (
                1e-6 * moment
            )
    assert 1e-3 < abs(plain.steps[1].tilt) < 3e-3
